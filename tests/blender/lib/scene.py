"""The Blender scene as a test sets it up."""


def select(objs, active=None):
    """Selects exactly `objs` (one object or a list) and makes `active` (by
    default the one object) the active one."""
    import bpy
    if not isinstance(objs, (list, tuple)):
        objs, active = [objs], objs if active is None else active
    for obj in bpy.context.scene.objects:
        obj.select_set(obj in objs)
    bpy.context.view_layer.objects.active = active


def lit_flat_scene(spp):
    """The clothbake scene (JSON, no objects yet) the material tests look at
    a 2 x 2 cloth at the origin in: a camera in front and above, 160 x 100;
    a sun and a point light; a black background; `spp` samples of the fibre
    model with the shadow march."""
    return {
        "camera": {"position": [0.0, -2.4, 1.8], "look_at": [0.0, 0.0, 0.0], "up": [0, 0, 1],
                   "fov_deg": 45, "fov_axis": "horizontal", "resolution": [160, 100]},
        "lights": [
            {"type": "directional", "direction": [0.35, 0.5, -0.8], "color": [1.0, 0.97, 0.92],
             "intensity": 3.0},
            {"type": "point", "position": [-1.3, -0.9, 1.1], "color": [0.85, 0.9, 1.0],
             "intensity": 2.0},
        ],
        "background": [0.0, 0.0, 0.0],
        "render": {"spp": spp, "step_cells": 0.5, "fiber_model": "table", "fiber_samples": 64,
                   "transmittance": "shadow-march", "shading": "fiber", "cutoff": 0.001,
                   "seed": 1},
    }
