bl_info = {
    "name": "clothbake",
    "author": "clothbake",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Object > clothbake",
    "description": "Render woven cloth from clothbake's baked view-dependent lookups "
                   "(Kimoto & Ohno's 3-D texture), in Cycles without OSL",
    "doc_url": "https://github.com/clothbake/clothbake/blob/main/docs/design/blender-nodes.md",
    "category": "Render",
}


def register():
    from .blender import registration
    registration.register()


def unregister():
    from .blender import registration
    registration.unregister()
