"""The node group: built once per pack, light layout and route, the steps
in the package docstring's order, and its users moved onto it."""
import bpy

from ..graph import Graph
from .address import crossing_address, texel_address
from .colours import coloured, strip_places, thread_places
from .common import mix
from .components import components
from .frame import shading_frame, view_direction
from .level import footprint_level
from .lights import UNITS, light_terms, world_terms
from .shaders import shaders
from .sockets import new_group
from .view import parallax_shift, randoms, view_node

GROUP_VERSION = 6


def _replace_old(name, group):
    """Every user of an older group of this name moved onto `group`, which
    takes the name (removing it would leave other objects' group nodes
    empty: a black plane once the sphere beside it was applied)."""
    old = bpy.data.node_groups.get(name)
    if old is not None and old != group:
        subs = [n.node_tree for n in old.nodes if n.type == "GROUP" and n.node_tree]
        old.user_remap(group)
        bpy.data.node_groups.remove(old)
        group.name = name
        for sub in subs:  # its sub-groups (SubGraph), unless used elsewhere
            if sub.users == 0:
                bpy.data.node_groups.remove(sub)


def light_kinds(lights):
    """Each light's kind as the group is built for it: SUN and POINT share
    one layout (the point flag tells them apart), SPOT and AREA have theirs."""
    return [o.data.type if o.data.type in ("SPOT", "AREA") else "POINT" for o in lights]


def layout_suffix(kinds):
    """The group's light layout in its name and key: "" when every light is
    a sun or a point light (the names groups had before spot and area
    lights), else " " and one letter a light (p, s, a)."""
    if all(k == "POINT" for k in kinds):
        return ""
    return " " + "".join({"POINT": "p", "SPOT": "s", "AREA": "a"}[k] for k in kinds)


def build_group(name, info, pack, coeff_image, light_image, kinds, route, strips=None,
                next_image=None, index_image=None, span_image=None):
    """The node group, reused when one of this name was built from the same
    pack; else built anew (the steps of the module docstring, in order) and
    every material of the old one moved onto it. `kinds`: per light, "POINT"
    (a sun or a point light), "SPOT" or "AREA" (light_kinds); an int n
    stands for n suns or point lights. A colour-free material: `strips`
    (Strips, its colour strips) and `next_image` (the pack's next atlas);
    the group then has the colour inputs. A material addressed per crossing
    (info.address CROSSINGS): `index_image`, the pack's crossings.exr, and on
    unevenly spaced threads `span_image`, its spans.exr."""
    if isinstance(kinds, int):
        kinds = ["POINT"] * kinds
    key = f"{GROUP_VERSION} {pack.folder} {pack.rank} {pack.dense} {len(kinds)}" \
          f"{layout_suffix(kinds)} {route} {pack.width}x{pack.height}"
    if "SPOT" in kinds:
        key += f" spot mask {UNITS.name}"     # the cone's mask changed in Blender 4.0
    if info.parallax_depth_mm > 0:
        key += f" parallax {info.parallax_depth_mm!r}"
    if index_image is not None:
        key += f" crossings {index_image.name} {info.ends}x{info.picks} {info.blocks}"
        if span_image is not None:
            key += f" spans {span_image.name}"
    if strips is not None:
        key += f" {info.parts} {strips.warp.name} {strips.q_warp} {tuple(strips.warp.size)}" \
               f" {strips.weft.name} {strips.q_weft} {tuple(strips.weft.size)}"
    old = bpy.data.node_groups.get(name)
    if old is not None and old.get("clothbake_key") == key:
        return old
    lit = route == "cycles-lit"
    group = new_group(name, key, kinds, strips, lit)
    g = Graph(group)
    gin = g.node("NodeGroupInput", 0).outputs
    frame = shading_frame(g, gin)
    position = frame.geometry.outputs["Position"]
    vz, view_side, vu, vv, scaled = view_direction(g, frame)
    xis = randoms(g, position, area="AREA" in kinds)
    xi1, xi2, xi3, xi4, xi5, xi6, xi7 = xis[:7]
    vi, view_row, vj = view_node(g, info.k, view_side, vu, vv, xi1, xi2)
    view = (vi, view_row)
    shift = parallax_shift(g, info, scaled, vi, vj) if info.parallax_depth_mm > 0 else None
    level = footprint_level(g, gin, info, position, vz, xi3)
    if index_image is not None:
        address = crossing_address(g, gin, info, pack, view, level, xi4, xi5, index_image,
                                    shift, span_image)
        places = thread_places(g, address[2], strips, info, 12)
        strip_levels = 1
    else:
        address = texel_address(g, gin, pack, info.k, view, level, xi4, xi5, shift)
        places = None if strips is None else strip_places(g, address[2], strips, 12)
        strip_levels = info.levels
    per_light, denom, col = light_terms(g, gin, frame, position, view, info, pack, kinds, lit,
                                    (xi6, xi7) + tuple(xis[7:]), 13)
    if lit:
        world, world_denom = world_terms(g, gin, view, pack, info.k, col)
        per_light += world
        denom = world_denom if denom is None else mix(g, "ADD", denom, world_denom, 1.0, col)
        col += 1
    if strips is None:
        sums, alpha, col = components(g, (coeff_image, light_image), address, per_light,
                                       info.k, pack, col)
    else:
        sums, alpha, col, sides = components(g, (coeff_image, light_image, next_image),
                                              address, per_light, info.k, pack, col)
        sums = coloured(g, gin, sums, places, sides, strips, strip_levels, col)
        col += 5
    shaders(g, sums, alpha, denom, lit, col)
    if g.late:
        bpy.data.node_groups.remove(group)
        raise RuntimeError(f"clothbake: node group '{name}' links out of creation order (a "
                           f"defect: Cycles would hold values on its SVM stack): {g.late[:5]}")
    _replace_old(name, group)
    return group
