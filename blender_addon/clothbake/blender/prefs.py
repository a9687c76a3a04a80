"""Add-on preferences: where the clothbake program is, and how many threads
it may use."""
import os
import shutil

import bpy

# The add-on's module: "clothbake" installed from a zip, or
# "bl_ext.REPOSITORY.clothbake" installed as an extension (4.2+).
ADDON_NAME = __package__.rsplit(".", 1)[0]


def default_program():
    """"clothbake" when it is on PATH, else the source tree's build
    (blender_addon/clothbake -> build/baker/clothbake) when the add-on runs
    from the repository, else "clothbake" (the user sets the path)."""
    if shutil.which("clothbake"):
        return "clothbake"
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # .../clothbake
    built = os.path.join(os.path.dirname(os.path.dirname(here)), "build", "baker", "clothbake")
    return built if os.access(built, os.X_OK) else "clothbake"


class CLOTHBAKE_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = ADDON_NAME

    program: bpy.props.StringProperty(
        name="clothbake program", subtype="FILE_PATH", default=default_program(),
        description="The clothbake program (a name on PATH or a path) that bakes, renders "
                    "references and compares")
    threads: bpy.props.IntProperty(
        name="Threads", default=0, min=0, max=1024,
        description="Worker threads of the clothbake program (0 = all cores)")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "program")
        layout.prop(self, "threads")
        found = program_path(context)
        layout.label(text=f"Using: {found}" if found else "Not found: set the path above",
                     icon="CHECKMARK" if found else "ERROR")


def preferences(context=None):
    """The add-on's preferences, or None when it is not registered as an add-on."""
    context = context or bpy.context
    addon = context.preferences.addons.get(ADDON_NAME)
    return addon.preferences if addon else None


def program_path(context=None):
    """Absolute path of the clothbake program, or None when not found."""
    prefs = preferences(context)
    program = prefs.program if prefs else default_program()
    program = bpy.path.abspath(program) if program.startswith("//") else program
    if os.sep in program:
        return program if os.access(program, os.X_OK) else None
    return shutil.which(program)


def threads(context=None):
    prefs = preferences(context)
    return prefs.threads if prefs else 0


CLASSES = (CLOTHBAKE_AP_preferences,)
