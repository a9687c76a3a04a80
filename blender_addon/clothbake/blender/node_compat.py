"""A node group's own sockets (its inputs and outputs), the one place that
knows how Blender names them. Up to 3.x a tree lists them in
`tree.inputs` / `tree.outputs`; from 4.0 those are gone and the sockets are
items of `tree.interface`. Every group the add-on builds makes and reads
its sockets through here, so the node trees come out the same in both."""


def new_group_socket(tree, in_out, socket_type, name):
    """Adds a socket to the group `tree` and returns it (set default_value,
    min_value, max_value on it). `in_out`: "INPUT" or "OUTPUT";
    `socket_type`: e.g. "NodeSocketFloat"."""
    if hasattr(tree, "interface"):
        return tree.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    sockets = tree.inputs if in_out == "INPUT" else tree.outputs
    return sockets.new(socket_type, name)


def group_sockets(tree, in_out):
    """The group's sockets of one side ("INPUT" or "OUTPUT"), in order; each
    has `name` and `identifier` (the key of a Geometry Nodes modifier's
    value)."""
    if hasattr(tree, "interface"):
        return [item for item in tree.interface.items_tree
                if item.item_type == "SOCKET" and item.in_out == in_out]
    return list(tree.inputs if in_out == "INPUT" else tree.outputs)


def set_modifier_input(mod, identifier, value):
    """Sets a Geometry Nodes modifier's input, keyed by its socket's
    `identifier`. Up to 4.x the value is an ID property of the modifier
    (`mod[identifier]`); 5.x refuses ID properties there and keeps the
    values under `mod.properties.inputs`, one item per socket with a
    `value` (measured in 5.2.2)."""
    props = getattr(mod, "properties", None)
    inputs = getattr(props, "inputs", None)
    if inputs is not None and hasattr(inputs, identifier):
        getattr(inputs, identifier).value = value
    else:
        mod[identifier] = value
