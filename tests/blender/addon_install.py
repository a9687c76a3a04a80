"""Headless Blender 3.4: the packaged add-on zip installs the way an artist
installs it (Preferences > Add-ons > Install), enables, registers its
operators, panel and preferences, and disables cleanly.

    blender -b --factory-startup --python-exit-code 1 -P addon_install.py -- ZIP USER_SCRIPTS

Run by run_addon_install.sh (BLENDER_USER_SCRIPTS points at USER_SCRIPTS).
"""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, failures, summary  # noqa: E402

zip_path, user_scripts = (os.path.abspath(a) for a in sys.argv[sys.argv.index("--") + 1:][:2])

result = bpy.ops.preferences.addon_install(filepath=zip_path)
installed = os.path.join(user_scripts, "addons", "clothbake", "__init__.py")
check(result == {"FINISHED"} and os.path.isfile(installed),
      f"installed into the user's add-ons ({installed})")
addon_utils.enable("clothbake", default_set=True, handle_error=None)
import clothbake  # noqa: E402
check(os.path.abspath(clothbake.__file__) == installed, "the installed copy is the one enabled")
check(addon_utils.check("clothbake")[1], "enabled")
for op in ("import_scene", "export_scene", "bake", "apply", "compare"):
    check(hasattr(bpy.types, f"CLOTHBAKE_OT_{op}") and
          hasattr(getattr(bpy.ops.clothbake, op), "poll"), f"operator clothbake.{op} registered")
check(hasattr(bpy.types, "CLOTHBAKE_PT_object"), "panel registered")
prefs = bpy.context.preferences.addons["clothbake"].preferences
check(prefs.program != "" and prefs.threads == 0, f"preferences ({prefs.program})")
addon_utils.disable("clothbake", default_set=True, handle_error=None)
check(not hasattr(bpy.types, "CLOTHBAKE_OT_bake") and not hasattr(bpy.types.Object, "clothbake"),
      "disabled cleanly")
summary()
sys.exit(1 if failures else 0)
