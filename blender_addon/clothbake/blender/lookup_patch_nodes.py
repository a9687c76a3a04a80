"""The geometry-nodes modifier that gives every face of the *evaluated* mesh
the vectors the lookup shader reads (clothbake.core.lookup_layout.face_attributes,
in object space): its bilinear patch (p0, e, f, g), its UV Jacobian terms
(ue, uf, ug) and its index.

Why a modifier and not attributes written from Python: Cycles renders the
mesh after its modifiers (a Subdivision Surface, a Cloth simulation, a
deform modifier), whose faces are not the base mesh's; attributes written
onto the base mesh would be copied or interpolated onto other faces. As the
last modifier of the stack, this node group sees exactly the faces Cycles
renders, in their order, in every frame, with no data stored per face.
Object space, because geometry nodes work there; the shader moves its
position and view vectors into object space (Vector Transform) and the
patch's derivatives back to world space for the frame, so a rotated,
scaled or parented object needs nothing more.

Corner order: "Corners of Face" with equal weights keeps the face's own
corner order (sort index i is the face's i-th corner), which is the order
the exported OBJ and so the lookup use.
"""
import bpy

from .graph import Graph
from .node_compat import group_sockets, new_group_socket, set_modifier_input

GROUP_NAME = "clothbake patch"
MODIFIER_NAME = "clothbake patch"
ATTR_PREFIX = "clothbake_"
FACE_ATTRS = ("p0", "e", "f", "g", "ue", "uf", "ug", "face")
_UV_INPUT = "UV map"


def _fresh_group():
    group = bpy.data.node_groups.get(GROUP_NAME)
    if group is not None:
        return group, False
    group = bpy.data.node_groups.new(GROUP_NAME, "GeometryNodeTree")
    new_group_socket(group, "INPUT", "NodeSocketGeometry", "Geometry")
    new_group_socket(group, "INPUT", "NodeSocketString", _UV_INPUT)
    new_group_socket(group, "OUTPUT", "NodeSocketGeometry", "Geometry")
    return group, True


def _build(group):
    g = Graph(group)
    inputs = g.node("NodeGroupInput", 0)
    position = g.node("GeometryNodeInputPosition", 0).outputs[0]
    index = g.node("GeometryNodeInputIndex", 0).outputs[0]
    uv = g.node("GeometryNodeInputNamedAttribute", 0, data_type="FLOAT_VECTOR")
    group.links.new(inputs.outputs[_UV_INPUT], uv.inputs["Name"])

    corners, points, uvs = [], [], []
    for i in range(4):
        corner = g.node("GeometryNodeCornersOfFace", 1)
        corner.inputs["Sort Index"].default_value = i
        corner_index = corner.outputs["Corner Index"]
        vertex = g.node("GeometryNodeVertexOfCorner", 2)
        group.links.new(corner_index, vertex.inputs["Corner Index"])
        at_point = g.node("GeometryNodeFieldAtIndex", 3, domain="POINT", data_type="FLOAT_VECTOR")
        group.links.new(vertex.outputs["Vertex Index"], at_point.inputs["Index"])
        group.links.new(position, _value_input(at_point))
        at_corner = g.node("GeometryNodeFieldAtIndex", 3, domain="CORNER",
                           data_type="FLOAT_VECTOR")
        group.links.new(corner_index, at_corner.inputs["Index"])
        group.links.new(uv.outputs["Attribute"], _value_input(at_corner))
        corners.append(corner_index)
        points.append(_value_output(at_point))
        uvs.append(_value_output(at_corner))

    def twist(c):  # c0 - c1 + c2 - c3
        return g.vmath("SUBTRACT", g.vmath("ADD", g.vmath("SUBTRACT", c[0], c[1], column=4), c[2],
                                           column=4), c[3], column=4)

    values = {
        "p0": points[0],
        "e": g.vmath("SUBTRACT", points[1], points[0], column=4),
        "f": g.vmath("SUBTRACT", points[3], points[0], column=4),
        "g": twist(points),
        "ue": g.vmath("SUBTRACT", uvs[1], uvs[0], column=4),
        "uf": g.vmath("SUBTRACT", uvs[3], uvs[0], column=4),
        "ug": twist(uvs),
        "face": g.combine(index, 0.0, 0.0, column=4),
    }
    geometry = inputs.outputs["Geometry"]
    for column, name in enumerate(FACE_ATTRS, start=5):
        store = g.node("GeometryNodeStoreNamedAttribute", column, data_type="FLOAT_VECTOR",
                       domain="FACE", label=name)
        store.inputs["Name"].default_value = ATTR_PREFIX + name
        group.links.new(geometry, store.inputs["Geometry"])
        group.links.new(values[name], _typed_input(store, "Value", "VECTOR"))
        geometry = store.outputs["Geometry"]
    out = g.node("NodeGroupOutput", len(FACE_ATTRS) + 5)
    group.links.new(geometry, out.inputs["Geometry"])


def _value_input(node):
    return _typed_input(node, "Value", "VECTOR")


def _value_output(node):
    for socket in node.outputs:
        if socket.name == "Value" and socket.type == "VECTOR" and socket.enabled:
            return socket
    raise RuntimeError(f"{node.bl_idname}: no vector Value output")


def _typed_input(node, name, kind):
    """The enabled input of that name and type (nodes with a data type keep
    one hidden socket per type)."""
    for socket in node.inputs:
        if socket.name == name and socket.type == kind and socket.enabled:
            return socket
    raise RuntimeError(f"{node.bl_idname}: no {kind} input '{name}'")


def patch_group():
    """The shared node group, built once per .blend."""
    group, fresh = _fresh_group()
    if fresh:
        _build(group)
    return group


def attach(obj, uv_name):
    """Adds (or refreshes) the modifier as the last of obj's stack, reading
    the UV map `uv_name`. Returns the modifier."""
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None or mod.type != "NODES":
        if mod is not None:
            obj.modifiers.remove(mod)
        mod = obj.modifiers.new(MODIFIER_NAME, "NODES")
    mod.node_group = patch_group()
    for socket in group_sockets(mod.node_group, "INPUT"):
        if socket.name == _UV_INPUT:
            set_modifier_input(mod, socket.identifier, uv_name)
    # Last in the stack: it must see the faces every other modifier makes.
    if obj.modifiers[-1] != mod:
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.modifier_move_to_index(modifier=mod.name,
                                                  index=len(obj.modifiers) - 1)
    mod.show_in_editmode = False
    obj.update_tag()
    return mod


def detach(obj):
    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is not None:
        obj.modifiers.remove(mod)
