"""Material Preview against Eevee's F12, measured in Blender's real window
(issues 22 and 24: "which works in Cycles, Eevee and Material Preview").
Run by material_preview.sh under Xvfb, from a timer so the window draws:

  1. the scene imported as the headless route does (clothbake's scene JSON,
     bilinear patches) and the cloth material applied on the exact route;
  2. Eevee's F12 render at SAMPLES anti-aliasing samples: OUT/eevee.exr;
  3. the 3D view put in Material Preview through the camera, the scene's
     world on (so the background matches F12's), overlays off, viewport
     samples SAMPLES;
     after the shaders compiled, View > Viewport Render Image
     (render.opengl in the view's context): OUT/preview.exr, and a
     screenshot OUT/preview_window.png.

    DISPLAY=:N blender --factory-startup -P material_preview.py -- \
        ADDON_DIR SCENE.json MATERIAL_DIR OUT_DIR SAMPLES
"""
import os
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
ADDON, SCENE, MATERIAL, OUT = (os.path.abspath(a) for a in argv[:4])
SAMPLES = int(argv[4])
bpy.context.preferences.view.show_splash = False
sys.path.insert(0, ADDON)
# The window driver the Blender tests use (tests/blender/lib/window.py).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "tests", "blender"))
from lib import window  # noqa: E402
state = {}


def view3d():
    return window.area("VIEW_3D")


def save_render(path):
    """The render result as a linear EXR through a temporary sibling (the
    headless route's writer; import_scene set the EXR format)."""
    from clothbake.blender.headless import _write_atomic_render
    _write_atomic_render(path, bpy.context.scene)


def setup():
    import addon_utils
    addon_utils.enable("clothbake", default_set=True)
    from clothbake.blender.headless import bilinear_patches
    from clothbake.blender.render_engines import use_eevee
    from clothbake.blender.material_apply import apply_material
    from clothbake.blender.scene_import import import_scene
    objects = import_scene(SCENE, clear=True, samples=SAMPLES)
    scene = bpy.context.scene
    use_eevee(scene, SAMPLES)
    scene.eevee.taa_samples = SAMPLES       # the viewport's (Material Preview's)
    for obj in objects:
        bilinear_patches(obj)
        _, notes = apply_material(obj, MATERIAL, route="exact", scene=scene)
        print("notes:", notes, flush=True)


def f12():
    t = time.time()
    bpy.ops.render.render(write_still=False)
    save_render(os.path.join(OUT, "eevee.exr"))
    print(f"eevee F12: {time.time() - t:.1f} s", flush=True)


def material_preview():
    win, area, reg = view3d()
    shading = area.spaces.active.shading
    shading.type = "MATERIAL"
    shading.use_scene_world = True
    area.spaces.active.overlay.show_overlays = False     # no grid, axes or light icons
    area.spaces.active.show_gizmo = False
    area.spaces.active.region_3d.view_perspective = "CAMERA"
    state["wait"] = time.time()


def compiled():
    return time.time() - state["wait"] > 30      # Eevee compiles in the background


def viewport_render():
    win, area, reg = view3d()
    t = time.time()
    with bpy.context.temp_override(window=win, area=area, region=reg):
        result = bpy.ops.render.opengl(view_context=True)
    print(f"viewport render: {result} {time.time() - t:.1f} s", flush=True)
    save_render(os.path.join(OUT, "preview.exr"))
    window.screenshot(os.path.join(OUT, "preview_window.png"))


STEPS = [setup, f12, material_preview, ("wait", compiled, 120), viewport_render]


window.drive(STEPS, os.path.join(OUT, "result.txt"), first_interval=3.0)
