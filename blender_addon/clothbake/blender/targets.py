"""Which objects an operator works on: the selected ones, else the active
one (what Blender's own operators do when nothing is selected)."""


def selected_else_active(context, keep=None):
    """The selected objects `keep` accepts (all when None), else the active
    object if it is accepted, else []."""
    accept = keep or (lambda obj: True)
    objs = [o for o in context.selected_objects if accept(o)]
    active = context.active_object
    if not objs and active is not None and accept(active):
        objs = [active]
    return objs


def is_mesh(obj):
    return obj.type == "MESH"
