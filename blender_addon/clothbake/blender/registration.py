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
    """Registers every module's classes, or none: should one fail, what was
    registered before it is unregistered again, so that a failed enable
    leaves no half-registered add-on behind."""
    import bpy
    done = []  # (module, classes registered) in order
    try:
        for mod in _modules():
            classes = []
            done.append((mod, classes))
            for cls in getattr(mod, "CLASSES", ()):
                bpy.utils.register_class(cls)
                classes.append(cls)
            if hasattr(mod, "register_extra"):
                mod.register_extra()
    except Exception:
        for mod, classes in reversed(done):
            if hasattr(mod, "unregister_extra"):
                try:
                    mod.unregister_extra()
                except Exception:  # its register_extra may not have run
                    pass
            for cls in reversed(classes):
                bpy.utils.unregister_class(cls)
        raise


def unregister():
    import bpy
    for mod in reversed(_modules()):
        if hasattr(mod, "unregister_extra"):
            mod.unregister_extra()
        for cls in reversed(getattr(mod, "CLASSES", ())):
            bpy.utils.unregister_class(cls)
