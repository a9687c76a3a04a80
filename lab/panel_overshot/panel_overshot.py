"""A real overshot draft baked from the panel at its defaults, in Blender's
real window (panel_overshot.sh). Driven from a timer (tests/blender/lib/window):

  1. the add-on enabled from the source tree, pointed at the program and
     nothing else set; the default scene's cube replaced by a plane of 64
     quads (its own UV map), made a cloth; the .blend saved;
  2. the WIF loaded as the file browser loads it; screenshot 01_loaded.png;
  3. Estimate: the panel gives the plan and the peak memory (02_estimate.png);
  4. Bake material: the estimate is over a minute, so the panel asks
     (03_confirm.png); answered as OK does; the bake runs in the
     background, its progress in the status bar (04_baking.png);
  5. baked: the material is applied; the 3D view in Material Preview
     (05_preview.png) and the panel (06_panel.png).

    DISPLAY=:N blender --factory-startup -P panel_overshot.py -- \
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR OUT_DIR WIF_FILE
"""
import json
import os
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
CLOTHBAKE, SOURCE, WORK, OUT, WIF = (os.path.abspath(a) for a in argv[:5])
sys.path.insert(0, os.path.join(SOURCE, "blender_addon"))
sys.path.insert(0, os.path.join(SOURCE, "tests", "blender"))
from lib import window  # noqa: E402
from lib.checks import check  # noqa: E402
bpy.context.preferences.view.show_splash = False
state = {}


def cloth_obj():
    return bpy.data.objects["Plane"]


def shot(name):
    return window.screenshot(os.path.join(OUT, name + ".png"))


def props():
    return window.area("PROPERTIES")


def scroll(down):
    win, area, region = props()
    with bpy.context.temp_override(window=win, area=area, region=region):
        for _ in range(8):
            bpy.ops.view2d.scroll_up(page=True)
        for _ in range(down // 40):
            bpy.ops.view2d.scroll_down()


def setup():
    import addon_utils
    addon_utils.enable("clothbake", default_set=True, handle_error=None)
    check(addon_utils.check("clothbake")[1], "1. add-on enabled from the source tree")
    bpy.context.preferences.addons["clothbake"].preferences.program = CLOTHBAKE
    cube = bpy.data.objects.get("Cube")
    if cube is not None:
        bpy.data.objects.remove(cube)
    bpy.ops.mesh.primitive_plane_add(size=2)
    obj = bpy.context.view_layer.objects.active
    obj.name = "Plane"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=7)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.clothbake.is_cloth = True
    props()[1].spaces.active.context = "OBJECT"
    path = os.path.join(WORK, "overshot.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    check(bpy.data.filepath == path, "1. a plane of 64 quads made a cloth, the .blend saved")


def load():
    cloth = cloth_obj().clothbake
    bpy.ops.clothbake.load_cloth(filepath=WIF, object_name=cloth.id_data.name)
    d = cloth.draft()
    check(cloth.wif_status == "" and d is not None,
          f"2. the WIF loaded: {d and d['ends']} x {d and d['picks']} threads "
          f"({cloth.wif_status or d.get('source_program', '')})")
    scroll(600)


def estimate():
    win, area, region = props()
    t = time.time()
    with bpy.context.temp_override(window=win, area=area, region=region):
        result = bpy.ops.clothbake.material_estimate()
    s = bpy.context.scene.clothbake
    check(result == {"FINISHED"}, f"3. Estimate in {time.time() - t:.0f} s: {s.material_estimate}")
    scroll(1700)


def bake():
    win, area, region = props()
    with bpy.context.temp_override(window=win, area=area, region=region):
        result = bpy.ops.clothbake.bake_material("INVOKE_DEFAULT")
    check(result == {"RUNNING_MODAL"}, f"4. Bake material asks first ({result})")


def confirmed():
    """OK in the dialog runs the operator's execute in the window."""
    win, area, region = props()
    with bpy.context.temp_override(window=win, area=area, region=region):
        result = bpy.ops.clothbake.bake_material("EXEC_DEFAULT")
    check(result == {"RUNNING_MODAL"}, f"4. confirmed, the bake runs ({result})")
    state["start"] = time.time()


def some_progress():
    return bpy.context.scene.clothbake.material_progress > 0.3


def baked():
    s = bpy.context.scene.clothbake
    folder = s.material_folder()
    path = os.path.join(folder, "manifest.json")
    m = json.load(open(path)) if os.path.isfile(path) else {}
    check(bool(m), f"5. baked in {time.time() - state['start']:.0f} s: {s.material_status}")
    print(f"     address {m.get('address')}, texels {m.get('texels')}, "
          f"blocks {m.get('crossings', {}).get('blocks')}", flush=True)
    mat = cloth_obj().active_material
    check(mat is not None and mat.get("clothbake_material") == folder,
          "5. the material is applied to the plane")
    win, area, region = window.area("VIEW_3D")
    area.spaces.active.shading.type = "MATERIAL"
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.view3d.view_selected()
    state["wait"] = time.time()


def compiled():
    return time.time() - state["wait"] > 30


STEPS = [setup, load, ("wait", lambda: True, 5), ("shot", "01_loaded"), estimate,
         ("shot", "02_estimate"), bake, ("shot", "03_confirm")]
if not os.environ.get("CLOTHBAKE_PANEL_NO_BAKE"):  # set: the estimate and the dialog only
    STEPS += [confirmed, ("wait", some_progress, 3000), ("shot", "04_baking"),
              ("wait", window.cleared("material_running"), 3000), baked,
              ("wait", compiled, 60), ("shot", "05_preview"), ("shot", "06_panel")]

os.makedirs(OUT, exist_ok=True)
window.drive(STEPS, os.path.join(WORK, "ui_result.txt"), shot=shot)
