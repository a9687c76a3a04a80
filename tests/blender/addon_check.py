"""What the headless add-on checks (addon_ui.py, addon_errors.py) share:
their arguments (CLOTHBAKE_EXE SOURCE_DIR WORK_DIR after Blender's "--"),
the add-on on sys.path, the test scenes, enabling the add-on, and
check()/run() that count failures and turn them into Blender's exit status;
and the image helpers the material tests share (pixels, rel_rmse,
render_still). Run by run_addon_script.sh."""
import os
import sys
import traceback

argv = sys.argv[sys.argv.index("--") + 1:]
CLOTHBAKE, SOURCE, TMP = (os.path.abspath(a) for a in argv[:3])
sys.path.insert(0, os.path.join(SOURCE, "blender_addon"))
PAPER = os.path.join(SOURCE, "testscenes", "paper", "scene.json")
SLAB = os.path.join(SOURCE, "testscenes", "slab", "scene.json")

failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


def enable_addon():
    """Enables the add-on from the source tree (checked), pointed at the
    program under test, one worker thread; returns its preferences."""
    import addon_utils
    import bpy
    addon_utils.enable("clothbake", default_set=True, handle_error=None)
    check(addon_utils.check("clothbake")[1], "add-on enabled from the source tree")
    prefs = bpy.context.preferences.addons["clothbake"].preferences
    prefs.program = CLOTHBAKE
    prefs.threads = 1
    return prefs


def run_checks(main):
    """Runs main(); a crash of the test itself is a failure, with its
    traceback. Exits 0 only when every check passed."""
    try:
        main()
    except Exception:
        traceback.print_exc()
        failures.append("exception")
    print(f"{len(failures)} failure(s)" if failures else "all checks passed", flush=True)
    sys.exit(1 if failures else 0)


def pixels(path):
    """An image's pixels as float32 (H, W, channels), through OpenImageIO."""
    import OpenImageIO as oiio
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)


def rel_rmse(a, b, mask=None):
    """Relative RMSE of b against a over their RGB (the first three
    channels; an (n, 3) array of masked pixels works as well), optionally
    over a mask: RMSE / a's mean."""
    import numpy as np
    a, b = a[..., :3], b[..., :3]
    if mask is not None:
        a, b = a[mask], b[mask]
    return float(np.sqrt(((a - b) ** 2).mean()) / max(1e-12, a.mean()))


def render_still(path, seed=1):
    """Renders the scene's camera with Cycles' seed `seed`, saves the
    result to `path` (as the scene's output settings say) and returns its
    pixels."""
    import bpy
    scene = bpy.context.scene
    scene.cycles.seed = seed
    bpy.ops.render.render(write_still=False)
    bpy.data.images["Render Result"].save_render(path, scene=scene)
    return pixels(path)
