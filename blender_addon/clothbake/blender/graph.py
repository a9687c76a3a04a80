"""A small helper for building shader node trees in code: each call adds one
node, links socket arguments and sets constant ones, and lays nodes out in
columns so the tree stays readable in the Node Editor."""

import bpy

from .node_compat import new_group_socket


class Graph:
    """Every helper makes (and converts) its inputs before its own node, so
    a node is made after every node it reads. Cycles' SVM compiler runs the
    nodes in the order they were made, in passes: a node that reads a later
    one waits a whole pass, while every node ready meanwhile is compiled and
    its outputs held on the 255-float stack. One such wait per group of
    components held every coefficient read at once ("out of SVM stack
    space", a black cloth, under three lights). `late` lists every link that
    breaks the order: a socket fed from a node made after it, or from a
    socket of another type (Cycles makes that ConvertNode after every node
    of the tree). Nodes Cycles expands (a Math node's own Clamp) are not
    used: math() makes the Clamp itself."""

    def __init__(self, tree):
        self.tree = tree
        self.nodes = tree.nodes
        self.links = tree.links
        self._column = {}
        self._serial = {}
        self.late = []

    def node(self, kind, column=0, label=None, **props):
        n = self.nodes.new(kind)
        self._serial[n.as_pointer()] = len(self._serial)
        row = self._column.get(column, 0)
        self._column[column] = row + 1
        n.location = (column * 220.0, -row * 160.0)
        if label:
            n.label = label
        for key, value in props.items():
            setattr(n, key, value)
        return n

    def feed(self, socket, value):
        """Links `value` into `socket` if it is a socket, else sets it. Make
        and convert `value` before the node of `socket` (ready)."""
        if hasattr(value, "is_output"):
            if value.id_data == self.tree:
                made = self._serial.get(value.node.as_pointer(), -1)
                if made > self._serial.get(socket.node.as_pointer(), -1):
                    self.late.append(f"{socket.node.name}.{socket.name} <- {value.node.name} "
                                     "(made after it)")
            if value.type != socket.type and "SHADER" not in (value.type, socket.type):
                self.late.append(f"{socket.node.name}.{socket.name} <- {value.node.name} "
                                 f"({value.type} into {socket.type})")
            self.links.new(value, socket)
        else:
            socket.default_value = value

    def ready(self, value, to):
        """`value` (a socket or a constant) as a socket of type `to`, made now,
        before its user (converted); constants pass through."""
        return self.converted(value, to) if hasattr(value, "is_output") else value

    def converted(self, out, to):
        """Output socket `out` as a socket of type `to` (VALUE, VECTOR or
        RGBA), through nodes made now; Cycles' own conversions: a float
        spread over three channels, colour and vector channel for channel.
        A conversion to VALUE is left to Cycles (none is used)."""
        frm = out.type
        if frm == to or to not in ("VECTOR", "RGBA") or frm not in ("VALUE", "VECTOR", "RGBA"):
            return out
        column = round(out.node.location.x / 220.0)
        if frm == "VALUE":
            xyz = (out, out, out)
        else:
            xyz = self.separate(out, column)
        if to == "VECTOR":
            return self.combine(*xyz, column=column)
        n = self.node("ShaderNodeCombineColor", column, mode="RGB")
        for i, c in enumerate(xyz):
            self.feed(n.inputs[i], c)
        return n.outputs[0]

    def math(self, op, a, b=0.0, c=0.0, column=0, clamp=False):
        """A Math node; clamp=True clamps to [0, 1] with a Clamp node made
        right after it, not the node's own Clamp: Cycles expands that into a
        Clamp node made after every node of the graph (MathNode::expand),
        and every user of a clamped value waited a compile pass (see the
        class docstring; the same operation, the same pixels)."""
        n = self.node("ShaderNodeMath", column, operation=op)
        self.feed(n.inputs[0], a)
        self.feed(n.inputs[1], b)
        if len(n.inputs) > 2:
            self.feed(n.inputs[2], c)
        if not clamp:
            return n.outputs[0]
        clamped = self.node("ShaderNodeClamp", column, clamp_type="MINMAX")
        self.feed(clamped.inputs["Value"], n.outputs[0])
        self.feed(clamped.inputs["Min"], 0.0)
        self.feed(clamped.inputs["Max"], 1.0)
        return clamped.outputs["Result"]

    def vmath(self, op, a, b=None, column=0):
        a, b = self.ready(a, "VECTOR"), None if b is None else self.ready(b, "VECTOR")
        n = self.node("ShaderNodeVectorMath", column, operation=op)
        self.feed(n.inputs[0], a)
        if b is not None:
            self.feed(n.inputs[1], b)
        # DOT_PRODUCT and LENGTH give a Value; the rest a Vector.
        return n.outputs["Value"] if op in ("DOT_PRODUCT", "LENGTH", "DISTANCE") else \
            n.outputs["Vector"]

    def combine(self, x, y, z=0.0, column=0):
        n = self.node("ShaderNodeCombineXYZ", column)
        self.feed(n.inputs[0], x)
        self.feed(n.inputs[1], y)
        self.feed(n.inputs[2], z)
        return n.outputs[0]

    def separate(self, v, column=0):
        """A vector's or a colour's three channels (a colour through Separate
        Color: no conversion)."""
        colour = hasattr(v, "is_output") and v.type == "RGBA"
        n = self.node("ShaderNodeSeparateColor" if colour else "ShaderNodeSeparateXYZ", column)
        if colour:
            n.mode = "RGB"
        self.feed(n.inputs[0], v)
        return n.outputs[0], n.outputs[1], n.outputs[2]

    def lerp(self, a, b, t, column=0):
        """a + (b - a) t for floats."""
        return self.math("MULTIPLY_ADD", self.math("SUBTRACT", b, a, column=column), t, a,
                         column=column)

    def mix_color(self, a, b, t, column=0):
        a, b = self.ready(a, "RGBA"), self.ready(b, "RGBA")
        n = self.node("ShaderNodeMixRGB", column, blend_type="MIX")
        self.feed(n.inputs["Fac"], t)
        self.feed(n.inputs["Color1"], a)
        self.feed(n.inputs["Color2"], b)
        return n.outputs["Color"]

    def scale(self, v, k, column=0):
        """Vector v times scalar k (socket or constant)."""
        v = self.ready(v, "VECTOR")
        n = self.node("ShaderNodeVectorMath", column, operation="SCALE")
        self.feed(n.inputs[0], v)
        self.feed(n.inputs["Scale"], k)
        return n.outputs["Vector"]


# The interface socket type of a group input or output fed by a socket of
# this type.
_INTERFACE_TYPES = {"VALUE": "NodeSocketFloat", "VECTOR": "NodeSocketVector",
                    "RGBA": "NodeSocketColor", "SHADER": "NodeSocketShader"}


class SubGraph(Graph):
    """Nodes built in a node group of their own, then placed in `parent` as
    one Group node. Blender 3.4 updates a whole tree after every new node
    or link (links.new took 22 ms each in a 750-node group), so one large
    tree costs the square of its size to build; pieces of it in groups of
    their own cost the sum of the squares of theirs. The group is complete
    before its Group node exists, so building it updates nothing else.

    A socket of another tree fed to one of this graph's nodes becomes a
    group input (one per socket); `finish(outputs)` adds the Group node to
    `parent` at `column`, links those sockets into it and returns its output
    sockets, one per socket of `outputs`. Cycles and Eevee flatten groups
    where their Group node stands among the parent's nodes, so the nodes
    keep the order they were made in."""

    def __init__(self, parent, name, column=0):
        super().__init__(bpy.data.node_groups.new(name, "ShaderNodeTree"))
        self.parent = parent
        self.column = column
        self._gin = self.nodes.new("NodeGroupInput")
        self._index = {}
        self._outer = []

    def feed(self, socket, value):
        if hasattr(value, "is_output") and value.id_data != self.tree:
            value = self._input(value)
        super().feed(socket, value)

    def _input(self, outer):
        key = outer.as_pointer()
        if key not in self._index:
            new_group_socket(self.tree, "INPUT", _INTERFACE_TYPES[outer.type],
                             f"in {len(self._outer)}")
            self._index[key] = len(self._outer)
            self._outer.append(outer)
        return self._gin.outputs[self._index[key]]

    def finish(self, outputs):
        gout = self.nodes.new("NodeGroupOutput")
        for i, s in enumerate(outputs):
            if s.id_data != self.tree:  # passed through untouched
                s = self._input(s)
            new_group_socket(self.tree, "OUTPUT", _INTERFACE_TYPES[s.type], f"out {i}")
            self.links.new(s, gout.inputs[i])
        self.parent.late += [f"{self.tree.name}: {e}" for e in self.late]
        node = self.parent.node("ShaderNodeGroup", self.column, node_tree=self.tree)
        for i, outer in enumerate(self._outer):
            self.parent.feed(node.inputs[i], outer)
        return [node.outputs[i] for i in range(len(outputs))]
