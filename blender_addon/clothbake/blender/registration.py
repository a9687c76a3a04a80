"""Registers the Blender classes of the add-on, in dependency order."""
import importlib

# Modules that define CLASSES (and optionally register_extra/unregister_extra).
_MODULES = ("prefs", "props", "operators_cloth", "operators_scene", "operators_lookup", "operators_compare",
            "operators_material", "wif_preview", "material_colours", "panels")


def _modules():
    mods = []
    for name in _MODULES:
        try:
            mods.append(importlib.import_module(f"{__package__}.{name}"))
        except ModuleNotFoundError as e:
            if e.name != f"{__package__}.{name}":
                raise
    return mods


def register():
    import bpy
    for mod in _modules():
        for cls in getattr(mod, "CLASSES", ()):
            bpy.utils.register_class(cls)
        if hasattr(mod, "register_extra"):
            mod.register_extra()


def unregister():
    import bpy
    for mod in reversed(_modules()):
        if hasattr(mod, "unregister_extra"):
            mod.unregister_extra()
        for cls in reversed(getattr(mod, "CLASSES", ())):
            bpy.utils.unregister_class(cls)
