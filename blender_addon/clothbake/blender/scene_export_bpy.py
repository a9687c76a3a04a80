"""Export, the Blender side: gathers the camera, lights, cloth objects,
background and settings of a Blender scene as plain data and hands them to
clothbake.core.scene_export, which builds and writes the scene.

What is exported: the scene camera (perspective, no lens shift), every
render-visible sun, point, spot and area light, every mesh object whose clothbake
"Cloth" box is ticked (the mesh Cycles renders: after its modifiers, at
their render settings, in world space, faces and corners in Blender's
order: face q is the lookup's quad q; the render-active UV map), the world's background colour and scene.clothbake's
reference render settings. Coordinates are written as they are (no axis
conversion), as import reads them.
"""
import math
import os
import re
import shutil
import tempfile
from contextlib import contextmanager

import bpy

from ..core import scene_export, scene_match
from ..core.errors import ClothbakeError
from ..core.light_units import effective_watts, unsupported_light_setting
from .running_units import RUNNING_UNITS as UNITS
from ..core.scene import load_scene
from . import evaluated_mesh

_LIGHT_NAME = re.compile(r"^clothbake light (\d+)$")


def cloth_objects(scene):
    """Mesh objects marked as cloth, in scene order: those imported in their
    scene's order (clothbake_object_index), then the others by name."""
    objs = [o for o in scene.objects if o.type == "MESH" and o.clothbake.is_cloth]
    return sorted(objs, key=lambda o: (0, o["clothbake_object_index"], o.name)
                  if isinstance(o.get("clothbake_object_index"), int) else (1, 0, o.name))


def _lights(scene):
    """(hint index or None, light object): imported lights in their scene
    order, then the others by name."""
    out = []
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        m = _LIGHT_NAME.match(obj.name)
        out.append((int(m.group(1)) if m else None, obj))
    return sorted(out, key=lambda e: (0, e[0], "") if e[0] is not None else (1, 0, e[1].name))


def hint_scene(scene):
    """The scene file this Blender scene came from, loaded, or None."""
    path = scene.clothbake.scene_path
    if not path:
        return None
    try:
        return load_scene(os.path.abspath(_abspath(path)))
    except ClothbakeError:
        return None


def _abspath(path):
    return bpy.path.abspath(path)


def _matrix(m):
    return [list(row) for row in m]


def _background(scene):
    world = scene.world
    if world is None:
        return [0.0, 0.0, 0.0]
    if world.use_nodes and world.node_tree:
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND":
                strength = node.inputs["Strength"].default_value
                return [c * strength for c in node.inputs["Color"].default_value[:3]]
    return list(world.color)


def mesh_data(obj):
    """QuadMeshData of a cloth object: the mesh Cycles renders (after its
    modifiers, at their render settings; evaluated_mesh), world positions,
    faces in order."""
    rm = evaluated_mesh.render_mesh(obj)
    try:
        return scene_export.quad_mesh(obj.name, rm.positions, rm.faces, rm.face_uvs)
    except ClothbakeError as e:
        why = evaluated_mesh.blame(obj, rm)
        if not why:
            raise
        raise ClothbakeError(e.message.replace("; clothbake", why + "; clothbake", 1)
                             if "; clothbake" in e.message else e.message + why,
                             e.path, e.field) from None


def light_watts(data):
    """A light's watts with its Exposure (Blender 5.x; 4.3 has none) applied."""
    return effective_watts(data.energy, getattr(data, "exposure", 0.0))


def unsupported_setting(data):
    """Why clothbake cannot light as this light does (Blender 5.x's
    Temperature, Normalize off), or None."""
    return unsupported_light_setting(getattr(data, "use_temperature", False),
                                     getattr(data, "normalize", True))


def light_settings(data):
    """What light_from_blender reads beyond type, colour and power: a spot's
    cone, an area light's shape, sizes and spread (None for the others)."""
    if data.type == "SPOT":
        return {"spot_size": data.spot_size, "spot_blend": data.spot_blend}
    if data.type == "AREA":
        return {"shape": data.shape, "size": data.size, "size_y": data.size_y,
                "spread": getattr(data, "spread", math.pi)}
    return None


def build_model(scene, supported_lights_only=False):
    """The export model of a Blender scene (clothbake.core.scene_export).
    Raises ClothbakeError naming what cannot be exported. With
    supported_lights_only (the material bake, which reads the cloth objects
    only) a light clothbake cannot model (an area light's spread below 180
    degrees, a spot scaled unevenly, ...) is left out instead of refused."""
    hint = hint_scene(scene)
    cam_obj = scene.camera
    if cam_obj is None or cam_obj.type != "CAMERA":
        raise ClothbakeError("the scene has no camera", "", "camera")
    cam = cam_obj.data
    if cam.type != "PERSP":
        raise ClothbakeError(f"camera '{cam_obj.name}' is {cam.type.lower()}; clothbake has a "
                             "perspective (pinhole) camera only", "", "camera")
    if abs(cam.shift_x) > 1e-9 or abs(cam.shift_y) > 1e-9:
        raise ClothbakeError(f"camera '{cam_obj.name}' has a lens shift; clothbake's camera "
                             "looks through the image centre", "", "camera")
    r = scene.render
    if abs(r.pixel_aspect_x - r.pixel_aspect_y) > 1e-9:
        raise ClothbakeError("non-square pixels (pixel aspect) are not supported", "", "camera")
    pct = r.resolution_percentage / 100.0
    resolution = [max(1, int(r.resolution_x * pct)), max(1, int(r.resolution_y * pct))]
    camera = scene_export.camera_from_blender(
        _matrix(cam_obj.matrix_world), cam.lens, cam.sensor_width, cam.sensor_height,
        cam.sensor_fit, resolution, hint=hint["camera"] if hint else None,
        look_distance=cam.dof.focus_distance if cam.dof.focus_distance > 0 else 1.0)

    lights = []
    for index, obj in _lights(scene):
        light_hint = None
        if hint is not None and index is not None and index < len(hint["lights"]):
            light_hint = hint["lights"][index]
        try:
            lights.append(scene_export.light_from_blender(
                obj.name, obj.data.type, _matrix(obj.matrix_world), obj.data.color,
                light_watts(obj.data), hint=light_hint, settings=light_settings(obj.data),
                units=UNITS, unsupported=unsupported_setting(obj.data)))
        except ClothbakeError:
            if not supported_lights_only:
                raise

    objects = []
    for obj in cloth_objects(scene):
        entry = obj.clothbake.to_scene_object()
        entry["mesh"] = mesh_data(obj)
        objects.append(entry)
    if not objects:
        raise ClothbakeError("no cloth objects: tick 'Cloth' in the clothbake panel "
                             "(Object properties) of a quad mesh with UVs", "", "objects")
    name = hint["name"] if hint else (os.path.splitext(os.path.basename(
        _abspath(scene.clothbake.scene_path)))[0] if scene.clothbake.scene_path else scene.name)
    return scene_export.build_scene(camera, lights, objects, _background(scene),
                                    scene.clothbake.render_dict(), name=name)


def export_scene(scene, path):
    """Writes the scene file (and its OBJs beside it); it becomes the
    scene's scene file. Returns the absolute path."""
    model = build_model(scene)
    path = scene_export.write_scene(model, _abspath(path))
    scene.clothbake.scene_path = path
    return path


@contextmanager
def scene_file_for_estimate(scene, supported_lights_only=False):
    """The scene file an estimate reads, which writes nothing and changes no
    setting: the scene file when it still describes the Blender scene, else
    an export to a temporary folder, removed when the block ends."""
    model = build_model(scene, supported_lights_only=supported_lights_only)
    settings = scene.clothbake
    current = os.path.abspath(_abspath(settings.scene_path)) if settings.scene_path else ""
    if current and scene_match.scene_matches_file(model, current):
        yield current
        return
    folder = tempfile.mkdtemp(prefix="clothbake_estimate_")
    try:
        yield scene_export.write_scene(model, os.path.join(folder, "scene.json"))
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def scene_file_for_bake(scene):
    """The scene file to bake: the scene file when it still describes the
    Blender scene, else a fresh export to BAKE_DIR.scene/scene.json (which
    becomes the scene file). Returns (path, exported)."""
    model = build_model(scene)
    settings = scene.clothbake
    current = os.path.abspath(_abspath(settings.scene_path)) if settings.scene_path else ""
    if current and scene_match.scene_matches_file(model, current):
        return current, False
    bake_dir = settings.bake_folder()
    if not bake_dir:
        raise ClothbakeError("set a bake folder (or export the scene first)", "", "bake folder")
    path = scene_export.write_scene(model, os.path.join(bake_dir + ".scene", "scene.json"))
    if not settings.bake_dir:
        settings.bake_dir = bake_dir  # keep the folder when the scene file changes
    settings.scene_path = path
    return path, True
