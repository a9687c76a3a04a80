"""The Blender scene as a test sets it up."""


def select(objs, active=None):
    """Selects exactly `objs` (one object or a list) and makes `active` (by
    default the one object) the active one."""
    import bpy
    if not isinstance(objs, (list, tuple)):
        objs, active = [objs], objs if active is None else active
    for obj in bpy.context.scene.objects:
        obj.select_set(obj in objs)
    bpy.context.view_layer.objects.active = active
