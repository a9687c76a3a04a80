"""The headless add-on tests' arguments (CLOTHBAKE_EXE SOURCE_DIR WORK_DIR
after Blender's "--"; `argv` holds them all), the add-on's source on
sys.path, the test scenes, and enable_addon(). Run by run_addon_script.sh."""
import os
import sys

from lib.checks import check

argv = sys.argv[sys.argv.index("--") + 1:]
CLOTHBAKE, SOURCE, TMP = (os.path.abspath(a) for a in argv[:3])
sys.path.insert(0, os.path.join(SOURCE, "blender_addon"))
PAPER = os.path.join(SOURCE, "testscenes", "paper", "scene.json")
SLAB = os.path.join(SOURCE, "testscenes", "slab", "scene.json")


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
