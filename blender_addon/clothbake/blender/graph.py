"""A small helper for building shader node trees in code: each call adds one
node, links socket arguments and sets constant ones, and lays nodes out in
columns so the tree stays readable in the Node Editor."""

import bpy


class Graph:
    def __init__(self, tree):
        self.tree = tree
        self.nodes = tree.nodes
        self.links = tree.links
        self._column = {}

    def node(self, kind, column=0, label=None, **props):
        n = self.nodes.new(kind)
        row = self._column.get(column, 0)
        self._column[column] = row + 1
        n.location = (column * 220.0, -row * 160.0)
        if label:
            n.label = label
        for key, value in props.items():
            setattr(n, key, value)
        return n

    def feed(self, socket, value):
        """Links `value` into `socket` if it is a socket, else sets it."""
        if hasattr(value, "is_output"):
            self.links.new(value, socket)
        else:
            socket.default_value = value

    def math(self, op, a, b=0.0, c=0.0, column=0, clamp=False):
        n = self.node("ShaderNodeMath", column, operation=op, use_clamp=clamp)
        self.feed(n.inputs[0], a)
        self.feed(n.inputs[1], b)
        if len(n.inputs) > 2:
            self.feed(n.inputs[2], c)
        return n.outputs[0]

    def vmath(self, op, a, b=None, column=0):
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
        n = self.node("ShaderNodeSeparateXYZ", column)
        self.feed(n.inputs[0], v)
        return n.outputs[0], n.outputs[1], n.outputs[2]

    def lerp(self, a, b, t, column=0):
        """a + (b - a) t for floats."""
        return self.math("MULTIPLY_ADD", self.math("SUBTRACT", b, a, column=column), t, a,
                         column=column)

    def mix_color(self, a, b, t, column=0):
        n = self.node("ShaderNodeMixRGB", column, blend_type="MIX")
        self.feed(n.inputs["Fac"], t)
        self.feed(n.inputs["Color1"], a)
        self.feed(n.inputs["Color2"], b)
        return n.outputs["Color"]

    def scale(self, v, k, column=0):
        """Vector v times scalar k (socket or constant)."""
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
            self.tree.inputs.new(_INTERFACE_TYPES[outer.type], f"in {len(self._outer)}")
            self._index[key] = len(self._outer)
            self._outer.append(outer)
        return self._gin.outputs[self._index[key]]

    def finish(self, outputs):
        gout = self.nodes.new("NodeGroupOutput")
        for i, s in enumerate(outputs):
            if s.id_data != self.tree:  # passed through untouched
                s = self._input(s)
            self.tree.outputs.new(_INTERFACE_TYPES[s.type], f"out {i}")
            self.links.new(s, gout.inputs[i])
        node = self.parent.node("ShaderNodeGroup", self.column, node_tree=self.tree)
        for i, outer in enumerate(self._outer):
            self.parent.feed(node.inputs[i], outer)
        return [node.outputs[i] for i in range(len(outputs))]
