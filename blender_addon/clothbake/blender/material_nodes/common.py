"""What the steps share: the names of the mesh attributes the group reads,
the tuples one step hands the next, and `mix`, the colour arithmetic every
step uses."""
from collections import namedtuple

STRETCH_ATTRIBUTE = "clothbake_world_per_uv"   # material_apply writes it
FRAME_SCALE_ATTRIBUTE = "clothbake_frame_scale"  # likewise: (e, 1 / e, depth ratio) per face
BLACK = (0.0, 0.0, 0.0, 1.0)

# The frame of step 1: `facing` is Geometry's normal (toward the viewer),
# `normal` the mesh's own side of it.
Frame = namedtuple("Frame", "geometry facing normal tangent bitangent scale")
# What the light loop hands the component loop, per light: the light-factor
# image's address and [(irradiance, accumulator: 0 radiance / front, 1 behind)].
LightTerm = namedtuple("LightTerm", "uv parts")
# The texel step 4 picked: the repeat coordinates (UV x repeats per UV), the
# picked texel's pixel centre in its tile (texel + 1.5: one past the
# gutter), the level's S_L and the level L.
Texel = namedtuple("Texel", "ux uy tx ty side_texels level")
# A colour-free material's colour strips (material_colours.py): the warp's
# and the weft's image, q (material repeats per colour repeat) and rows per
# level (core/yarn_colours.strip_layout).
Strips = namedtuple("Strips", "warp weft q_warp q_weft rows_warp rows_weft")


def mix(g, blend, a, b, fac, column):
    """Colour a (blend) b by fac, factor and result unclamped (Blender 3.4's
    Mix node; the legacy MixRGB clamps fac in Eevee). Colours throughout:
    a float or vector into a colour socket makes Cycles insert a conversion
    node after all others, which delays its users to a later compile pass
    while every ready texture read is compiled and held on the 255-float SVM
    stack ("out of SVM stack space": a black cloth at rank 24)."""
    a, b = g.ready(a, "RGBA"), g.ready(b, "RGBA")
    n = g.node("ShaderNodeMix", column, data_type="RGBA", blend_type=blend,
               clamp_factor=False, clamp_result=False)
    g.feed(n.inputs[0], fac)
    g.feed(n.inputs[6], a)
    g.feed(n.inputs[7], b)
    return n.outputs[2]
