"""Headless Blender: the packaged add-on installs the way an artist installs
it, enables, registers its operators, panel and preferences, and disables
cleanly; a Blender that lacks what it needs gets one sentence and keeps
nothing registered.

    blender -b --factory-startup --python-exit-code 1 -P addon_install.py -- \
        ZIP USER_SCRIPTS [EXTENSION_ZIP]

- ZIP, the legacy add-on: Preferences > Add-ons > Install (Install from Disk
  from 4.2), into USER_SCRIPTS (BLENDER_USER_SCRIPTS points there).
- EXTENSION_ZIP (Blender 4.2 and newer): the extension installed into the
  user's extension repository (BLENDER_USER_EXTENSIONS points into the test's
  folder), as bl_ext.user_default.clothbake.
- Without numpy (blocked for this check), on a Blender older than the
  minimum (raised for this check) and with a registration that fails
  half-way, enabling fails with one sentence and leaves no class or property
  behind.

Run by run_addon_install.sh.
"""
import os
import shutil
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, failures, summary  # noqa: E402

args = [os.path.abspath(a) for a in sys.argv[sys.argv.index("--") + 1:]]
zip_path, user_scripts = args[:2]
extension_zip = args[2] if len(args) > 2 else None
print(f"Blender {bpy.app.version_string}, Python {sys.version.split()[0]}")


def registered_nothing():
    return (not any(name.startswith("CLOTHBAKE_") for name in dir(bpy.types))
            and not hasattr(bpy.types.Object, "clothbake"))


def enable_error(module):
    """Enables `module`; the exception it raised, or None."""
    errors = []
    addon_utils.enable(module, default_set=True, handle_error=errors.append)
    return errors[0] if errors else None


def check_enabled(module, where):
    check(addon_utils.check(module)[1], f"{where}: enabled")
    for op in ("import_scene", "export_scene", "bake", "apply", "compare", "bake_material",
               "apply_material"):
        check(hasattr(bpy.types, f"CLOTHBAKE_OT_{op}"), f"{where}: operator clothbake.{op} registered")
    check(hasattr(bpy.types, "CLOTHBAKE_PT_object"), f"{where}: panel registered")
    prefs = bpy.context.preferences.addons[module].preferences
    check(prefs.program != "" and prefs.threads == 0, f"{where}: preferences ({prefs.program})")
    addon_utils.disable(module, default_set=True, handle_error=None)
    check(registered_nothing(), f"{where}: disabled cleanly")


def drop_modules(package):
    for name in [n for n in sys.modules if n == package or n.startswith(package + ".")]:
        del sys.modules[name]


# The legacy zip.
result = bpy.ops.preferences.addon_install(filepath=zip_path)
installed = os.path.join(user_scripts, "addons", "clothbake", "__init__.py")
check(result == {"FINISHED"} and os.path.isfile(installed),
      f"zip installed into the user's add-ons ({installed})")

# A Blender whose Python has no numpy (as Debian's blender without its
# recommends): one sentence naming numpy and the package, nothing registered.
saved_numpy = sys.modules.get("numpy")
sys.modules["numpy"] = None  # import numpy now raises; find_spec finds nothing
error = enable_error("clothbake")
if saved_numpy is not None:
    sys.modules["numpy"] = saved_numpy
else:
    del sys.modules["numpy"]
message = str(error) if error else ""
check(error is not None and "numpy" in message and "python3-numpy" in message and "\n" not in message,
      f"without numpy: one sentence ({message})")
check(registered_nothing(), "without numpy: nothing registered")
addon_utils.disable("clothbake", default_set=True, handle_error=None)
drop_modules("clothbake")

# A Blender older than the add-on supports (its minimum raised past this
# one's for the check): one sentence naming the version, nothing registered.
import clothbake  # noqa: E402  (the zip's copy, not enabled yet)
clothbake.MIN_BLENDER = (bpy.app.version[0] + 1, 0, 0)
clothbake.__time__ = os.path.getmtime(clothbake.__file__)  # else enable reloads it
error = enable_error("clothbake")
message = str(error) if error else ""
check(error is not None and f"needs Blender {bpy.app.version[0] + 1}.0.0 or newer" in message
      and bpy.app.version_string in message and "\n" not in message,
      f"too old a Blender: one sentence ({message})")
check(registered_nothing(), "too old a Blender: nothing registered")
addon_utils.disable("clothbake", default_set=True, handle_error=None)
drop_modules("clothbake")

# A registration that fails half-way (the panel refused): what was
# registered before it is unregistered again.
real_register = bpy.utils.register_class


def refuse_panel(cls):
    if cls.__name__ == "CLOTHBAKE_PT_object":
        raise RuntimeError("refused for the test")
    real_register(cls)


bpy.utils.register_class = refuse_panel
error = enable_error("clothbake")
bpy.utils.register_class = real_register
check(error is not None and "refused for the test" in str(error), "a failing registration fails the enable")
check(registered_nothing(), "a failing registration leaves nothing registered")
addon_utils.disable("clothbake", default_set=True, handle_error=None)
drop_modules("clothbake")

error = enable_error("clothbake")
check(error is None, f"zip: enables ({error})")
import clothbake  # noqa: E402
check(os.path.abspath(clothbake.__file__) == installed, "zip: the installed copy is the one enabled")
check_enabled("clothbake", "zip")

# The extension (4.2+): Blender's own install of the built package.
if extension_zip:
    # The zip's copy removed by hand (addon_remove wants a window to redraw).
    shutil.rmtree(os.path.dirname(installed))
    drop_modules("clothbake")
    result = bpy.ops.extensions.package_install_files(filepath=extension_zip, repo="user_default",
                                                      enable_on_install=False)
    module = "bl_ext.user_default.clothbake"
    check(result == {"FINISHED"}, f"extension installed ({extension_zip})")
    error = enable_error(module)
    check(error is None, f"extension: enables ({error})")
    check_enabled(module, "extension")

summary()
sys.exit(1 if failures else 0)
