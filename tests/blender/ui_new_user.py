"""The new user's first minutes, in Blender's real window (what an artist
meets first: install, a plane, Bake, Apply, F12, Compare, the material),
driven step by step from a timer (lib.window) so the window draws between
steps:

  1. the add-on installed from its zip (Preferences > Add-ons > Install)
     and enabled, pointed at the program under test;
  2. Blender's default scene: the cube deleted, a 2 x 2 plane added
     (rotation (0.9, 0, 0.3)) and subdivided with 7 cuts in Edit Mode,
     'Cloth' ticked, a bake folder set, every other setting at the panel's
     default;
  3. Bake pressed (invoked as the button does: modal, in the background,
     with progress), waited for;
  4. Apply; the render engine switched to Cycles: the panel warns that this
     Blender has no denoiser; its button pressed;
  5. F12 (render.render invoked as the key does), waited for, saved;
  6. Compare;
  7. the cloth material: a UV sphere added (triangles at its
     poles), the plane's weave set to the Twill 2/1 preset, Bake material
     pressed with small settings (modal, waited for) and so applied to the
     selected plane and sphere; Apply material again; the 3D view switched
     to Material Preview; then the light moved (the material's drivers
     follow it). Screenshots material_NN_*.png;
  8. a full bake at the old defaults: Bake asks first.

A screenshot of the window after each step goes to OUT_DIR/NN_step.png.
Each step's outcome is checked; the shell script (ui_new_user.sh) then
compares Compare's Cycles render with `clothbake lookup-render`.

    DISPLAY=:N blender --factory-startup -P ui_new_user.py -- \
        CLOTHBAKE_EXE ADDON_ZIP WORK_DIR OUT_DIR
"""
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib import window  # noqa: E402
from lib.checks import check  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
CLOTHBAKE, ZIP, WORK, OUT = (os.path.abspath(a) for a in argv[:4])
bpy.context.preferences.view.show_splash = False
region = window.region


def shot(name, newest_window=False):
    """Screenshot of the main window (scrolled to the clothbake panel), or
    of the newest one (F12's render window, Compare's sheet)."""
    windows = bpy.context.window_manager.windows
    win = windows[-1] if newest_window else windows[0]
    if not newest_window:
        _, props, _ = window.area("PROPERTIES")
        if props is not None:
            with bpy.context.temp_override(window=win, area=props, region=region(props)):
                for _ in range(6):
                    bpy.ops.view2d.scroll_down(page=True)
    for area in win.screen.areas:
        if newest_window and area.type == "IMAGE_EDITOR":
            with bpy.context.temp_override(window=win, area=area, region=region(area)):
                bpy.ops.image.view_all(fit_view=True)
    window.screenshot(os.path.join(OUT, name + ".png"))


def in_properties(op, *args, **kwargs):
    """Runs an operator as a button of the Properties editor does."""
    win, area, _ = window.area("PROPERTIES")
    with bpy.context.temp_override(window=win, area=area, region=region(area)):
        return op(*args, **kwargs)


def in_view3d(op, *args, **kwargs):
    win, area, _ = window.area("VIEW_3D")
    with bpy.context.temp_override(window=win, area=area, region=region(area)):
        return op(*args, **kwargs)


def install():
    result = bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    check(result == {"FINISHED"}, "1. add-on installed from the zip")
    bpy.ops.preferences.addon_enable(module="clothbake")
    import addon_utils
    check(addon_utils.check("clothbake")[1], "1. add-on enabled")
    prefs = bpy.context.preferences.addons["clothbake"].preferences
    prefs.program = CLOTHBAKE


def make_plane():
    cube = bpy.data.objects.get("Cube")
    if cube is not None:
        bpy.data.objects.remove(cube)
    in_view3d(bpy.ops.mesh.primitive_plane_add, size=2, rotation=(0.9, 0.0, 0.3))
    obj = bpy.context.view_layer.objects.active
    in_view3d(bpy.ops.object.mode_set, mode="EDIT")
    in_view3d(bpy.ops.mesh.subdivide, number_cuts=7)
    in_view3d(bpy.ops.object.mode_set, mode="OBJECT")
    check(len(obj.data.polygons) == 64, "2. a plane of 64 quads made in Blender")
    obj.clothbake.is_cloth = True
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 480, 270
    scene.clothbake.bake_dir = os.path.join(WORK, "bake")
    _, props, _ = window.area("PROPERTIES")
    props.spaces.active.context = "OBJECT"


def estimate():
    result = in_properties(bpy.ops.clothbake.estimate)
    text = bpy.context.scene.clothbake.bake_estimate
    check(result == {"FINISHED"} and text.startswith("about "),
          f"3. Estimate before baking: {text}")


def started(op, what):
    """A step: clothbake.<op> invoked as its button does (modal, in the
    background), checked running."""
    def step():
        result = in_properties(getattr(bpy.ops.clothbake, op), "INVOKE_DEFAULT")
        check(result == {"RUNNING_MODAL"}, f"{what} runs in the background ({result})")
    step.__name__ = f"start_{op}"
    return step


def apply_and_cycles():
    settings = bpy.context.scene.clothbake
    check(settings.bake_status.startswith("baked"), f"3. Bake finished: {settings.bake_status}")
    check(in_properties(bpy.ops.clothbake.apply) == {"FINISHED"}, "4. Apply")
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    from clothbake.blender.operators_compare import denoiser_missing
    import _cycles
    if not _cycles.with_openimagedenoise:
        check(denoiser_missing(scene), "4. the panel warns: no denoiser, F12 would fail")


def denoising_off():
    from clothbake.blender.operators_compare import denoiser_missing
    scene = bpy.context.scene
    if denoiser_missing(scene):
        check(in_properties(bpy.ops.clothbake.denoising_off) == {"FINISHED"} and
              not scene.cycles.use_denoising, "4. its button turns render denoising off")


def start_render():
    win, area, _ = window.area("VIEW_3D")
    with bpy.context.temp_override(window=win, area=area):
        result = bpy.ops.render.render("INVOKE_DEFAULT")
    check(result == {"RUNNING_MODAL"}, f"5. F12 renders ({result})")


def render_done():
    return not bpy.app.is_job_running("RENDER")


def after_render():
    image = bpy.data.images["Render Result"]
    scene = bpy.context.scene
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    path = os.path.join(WORK, "f12.exr")
    image.save_render(path, scene=scene)
    check(os.path.isfile(path), "5. F12's image saved")


def compare():
    result = in_properties(bpy.ops.clothbake.compare)
    settings = bpy.context.scene.clothbake
    check(result == {"FINISHED"}, f"6. Compare: {settings.compare_status}")


def long_bake_asks():
    """The old defaults (a full bake, 64 texels, 4 samples: about 8 minutes
    here) ask before they start: Bake opens a dialog and runs nothing."""
    from clothbake.blender.operators_lookup import CLOTHBAKE_OT_bake
    settings = bpy.context.scene.clothbake
    settings.adaptive = False
    settings.texels, settings.bake_spp = 64, 4
    result = in_properties(bpy.ops.clothbake.bake, "INVOKE_DEFAULT")
    check(result == {"RUNNING_MODAL"} and not CLOTHBAKE_OT_bake._running and
          not settings.bake_running,
          f"7. a long bake ({settings.bake_estimate}) asks first and has not started")


def shaders_compiled():
    """Eevee compiles the material's shaders in the background after Material
    Preview is switched on ("Compiling Shaders" in the view): waits 20 s."""
    state.setdefault("wait_start", time.time())
    if time.time() - state["wait_start"] < 20:
        return False
    del state["wait_start"]
    return True


def material_setup():
    scene = bpy.context.scene
    plane = next(o for o in scene.objects if o.type == "MESH" and o.clothbake.is_cloth)
    in_view3d(bpy.ops.mesh.primitive_uv_sphere_add, radius=0.6, location=(1.6, 0.0, 0.6))
    sphere = bpy.context.view_layer.objects.active
    sphere.name = "Sphere"
    tris = sum(1 for p in sphere.data.polygons if len(p.vertices) == 3)
    check(tris > 0 and sphere.data.uv_layers, f"8. a UV sphere with {tris} triangles")
    plane.clothbake.weave = "twill_2_1"
    settings = scene.clothbake
    settings.material_dir = os.path.join(WORK, "material")
    settings.material_texels, settings.material_directions = 16, 6
    settings.material_light_directions, settings.material_spp = 6, 1
    for obj in scene.objects:
        obj.select_set(obj in (plane, sphere))
    bpy.context.view_layer.objects.active = plane
    _, props, _ = window.area("PROPERTIES")
    props.spaces.active.context = "OBJECT"


def material_estimate():
    result = in_properties(bpy.ops.clothbake.material_estimate)
    text = bpy.context.scene.clothbake.material_estimate
    check(result == {"FINISHED"} and text.startswith("about ") and
          not os.path.exists(os.path.join(WORK, "material")),
          f"8. material Estimate: {text}, nothing written")


def material_baked():
    import json
    settings = bpy.context.scene.clothbake
    folder = os.path.join(WORK, "material")
    manifest = os.path.join(folder, "manifest.json")
    fmt = json.load(open(manifest))["format"] if os.path.isfile(manifest) else None
    check(fmt == "clothbake-material" and settings.material_status.startswith("baked"),
          f"8. Bake material finished: {settings.material_status}")
    objs = [o for o in bpy.context.scene.objects if o.select_get()]
    check(len(objs) == 2 and all(o.active_material is not None and
                                 o.active_material.get("clothbake_material") == folder
                                 for o in objs),
          "8. the material is on the plane and the sphere")


def apply_material():
    check(in_properties(bpy.ops.clothbake.apply_material) == {"FINISHED"}, "8. Apply material")


def material_preview():
    win, area, _ = window.area("VIEW_3D")
    area.spaces.active.shading.type = "MATERIAL"
    with bpy.context.temp_override(window=win, area=area, region=region(area)):
        bpy.ops.view3d.view_selected()
    check(area.spaces.active.shading.type == "MATERIAL", "8. the 3D view in Material Preview")


def move_light():
    light = bpy.data.objects.get("Light")
    check(light is not None, "8. the default scene's light is there to move")
    if light is not None:
        state["light_at"] = tuple(light.location)
        light.location = (-3.0, -4.0, 5.0)  # still above the plane, from the other side
    if os.environ.get("CLOTHBAKE_UI_SAVE"):  # for looking at the scene afterwards
        bpy.ops.wm.save_as_mainfile(filepath=os.environ["CLOTHBAKE_UI_SAVE"], copy=True)


def restore_scene():
    """The plane's weave back to plain and the light back: step 8's estimate
    then finds the scene of the lookup bake unchanged (no re-export), and the
    shell script renders that bake from its scene file."""
    plane = next(o for o in bpy.context.scene.objects if o.type == "MESH" and o.clothbake.is_cloth)
    plane.clothbake.weave = "plain"
    if "light_at" in state:
        bpy.data.objects["Light"].location = state["light_at"]


# The steps; a step that is a predicate waits until it holds (or times out).
# ("shot", name, newest window) runs a tick after the step before it, once the
# window has redrawn.
STEPS = [install, ("shot", "01_installed", False), make_plane, ("shot", "02_panel", False),
         estimate, ("shot", "03_estimate", False), started("bake", "3. Bake"), ("wait", window.cleared("bake_running"), 600),
         ("shot", "04_baked", False), apply_and_cycles, ("shot", "05_denoiser_warning", False),
         denoising_off, ("shot", "06_denoising_off", False), start_render,
         ("wait", render_done, 300), after_render, ("shot", "07_f12", True), compare,
         ("shot", "08_compare", True), material_setup, material_estimate, ("shot", "material_01_panel", False),
         started("bake_material", "8. Bake material"), ("shot", "material_02_baking", False), ("wait", window.cleared("material_running"), 600),
         material_baked, ("shot", "material_03_baked", False), apply_material,
         material_preview, ("wait", shaders_compiled, 120),
         ("shot", "material_04_preview", False), move_light, ("wait", shaders_compiled, 120),
         ("shot", "material_05_light_moved", False), restore_scene,
         long_bake_asks, ("shot", "09_long_bake_asks", False)]
state = {}
os.makedirs(OUT, exist_ok=True)
window.drive(STEPS, os.path.join(WORK, "ui_result.txt"), shot=shot)
