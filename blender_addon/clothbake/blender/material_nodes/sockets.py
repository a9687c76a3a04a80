"""The group's sockets: the inputs the drivers feed (material_drivers.py)
and the outputs the material reads, made through node_compat."""
import bpy

from ..node_compat import new_group_socket


def _inputs(group, kinds):
    """The group's inputs. Per light l: its vector (a sun's direction toward
    it, else its position: a spot's apex, an area light's centre), its
    irradiance (colour x power x the watts' factor, 0 when hidden) and the
    point flag; a spot's axis (the way it shines), cos(size / 2) and the
    smoothstep's width on the cosine; an area light's axis (its emitting
    normal), its two sides as world vectors (size x scale along the light's
    X and Y) and the ellipse flag (disk, ellipse)."""
    def new(socket_type, name):
        return new_group_socket(group, "INPUT", socket_type, name)

    new("NodeSocketVector", "UV")
    new("NodeSocketVector", "Tangent")
    new("NodeSocketVector", "Bitangent")
    for name, value in (("Repeats per UV", 40.0), ("World per UV", 1.0),
                        ("Pixel angle", 1e-3), ("Samples", 16.0), ("Footprint scale", 1.0)):
        new("NodeSocketFloat", name).default_value = value
    for l, kind in enumerate(kinds):
        new("NodeSocketVector", f"Light {l} vector")
        new("NodeSocketVector", f"Light {l} irradiance")
        new("NodeSocketFloat", f"Light {l} point")
        if kind in ("SPOT", "AREA"):
            new("NodeSocketVector", f"Light {l} axis").default_value = (0.0, 0.0, -1.0)
        if kind == "SPOT":
            new("NodeSocketFloat", f"Light {l} cos half angle").default_value = 0.0
            new("NodeSocketFloat", f"Light {l} smooth").default_value = 0.0
        if kind == "AREA":
            new("NodeSocketVector", f"Light {l} side u").default_value = (1.0, 0.0, 0.0)
            new("NodeSocketVector", f"Light {l} side v").default_value = (0.0, 1.0, 0.0)
            new("NodeSocketFloat", f"Light {l} ellipse").default_value = 0.0


def _colour_inputs(group):
    """A colour-free material's yarn colours: each family's colour, and
    whether its threads take theirs from the family's strips instead (1: a
    per-thread sequence; 0: every thread the family's colour)."""
    def new(socket_type, name):
        return new_group_socket(group, "INPUT", socket_type, name)

    for family in ("Warp", "Weft"):
        new("NodeSocketColor", f"{family} colour").default_value = (0.5, 0.5, 0.5, 1.0)
    for family in ("Warp", "Weft"):
        s = new("NodeSocketFloat", f"{family} per thread")
        s.default_value, s.min_value, s.max_value = 0.0, 0.0, 1.0


def new_group(name, key, kinds, strips=None, lit=False):
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    group["clothbake_key"] = key
    _inputs(group, kinds)
    if lit:
        # The world's radiance, uniform (material_drivers.drive_world): the
        # cycles-lit route's world term (world_terms).
        new_group_socket(group, "INPUT", "NodeSocketVector", "World radiance")
    if strips is not None:
        _colour_inputs(group)
    for socket_type, name in (("NodeSocketShader", "Shader"), ("NodeSocketColor", "Color"),
                              ("NodeSocketFloat", "Alpha")):
        new_group_socket(group, "OUTPUT", socket_type, name)
    return group
