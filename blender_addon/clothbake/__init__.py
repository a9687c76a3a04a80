bl_info = {
    "name": "clothbake",
    "author": "clothbake",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Object > clothbake",
    "description": "Render woven cloth from clothbake's baked view-dependent lookups "
                   "(Kimoto & Ohno's 3-D texture), in Cycles without OSL",
    "doc_url": "https://github.com/clothbake/clothbake/blob/main/docs/guide/blender.md",
    "category": "Render",
}

# The oldest Blender the add-on is tested on (docs/guide/blender.md lists the
# tested versions); blender_manifest.toml states the extension's own minimum.
MIN_BLENDER = (3, 4, 0)


class MissingRequirement(RuntimeError):
    """What this Blender lacks for the add-on, in one sentence a user can act on."""


def requirements_missing():
    """The sentence saying what this Blender lacks, or None. Checked before
    any of the add-on's modules is imported, so that nothing is registered
    when it fails."""
    import bpy
    if tuple(bpy.app.version) < MIN_BLENDER:
        return (f"clothbake needs Blender {'.'.join(map(str, MIN_BLENDER))} or newer; this is "
                f"{bpy.app.version_string}: install a newer Blender (Debian 12 and later ship one)")
    try:
        import numpy  # noqa: F401  (the add-on's modules import it at load)
    except ImportError:
        return ("clothbake needs numpy, which this Blender's Python cannot import: install it "
                "(Debian and Ubuntu: apt install python3-numpy; Blender from blender.org "
                "bundles it) and enable the add-on again")
    return None


def register():
    missing = requirements_missing()
    if missing:
        print(f"clothbake: error: {missing}")
        raise MissingRequirement(missing)
    from .blender import registration
    registration.register()


def unregister():
    from .blender import registration
    registration.unregister()
