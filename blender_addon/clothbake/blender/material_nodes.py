"""The cloth material's node group (docs/material-format.md), plain nodes
that Cycles, Eevee and the viewport's Material Preview all run. Nothing is
stored per face but the UV map's local scale (an attribute read for the
level). Per shading point the group computes, one function a step:
  1. the frame (_frame): N the true normal (Geometry's, unflipped with
     Backfacing), T the UV map's tangent made orthogonal to N, B = s N x T
     with s = +-1 the UV map's handedness there (the sign of a Normal Map
     node's signed bitangent, below), so B follows dP/dv on islands laid
     against the face winding too;
     the directions toward the eye (_view_direction) and toward each light
     (_light) in that frame;
  2. where in the repeat (_texel_address): the UV map x repeats per UV, its
     fraction; for a material addressed per crossing (_crossing_address),
     the crossing and the texel in it, each crossing S_L texels a side
     whatever its width, the tap's block read from the pack's per-crossing
     index (a Closest read), its colours a column a thread (_thread_places);
  3. the level from the pixel's footprint (_level, below);
  4. the view node (_view_node), level and texel, each picked at random with
     the probabilities of clothbake's bilinear / trilinear weights (a White
     Noise of the position, _randoms: every sample of a pixel hits another
     point), so that one read of the Blender images
     (clothbake.core.material_pack) per component replaces 4 views x 2
     levels x 4 texels; the pixel's samples average the blend ("stochastic
     texture filtering"). Every image is read with Closest: nothing bleeds
     between tiles, and Eevee's GPU mip-maps (which an atlas cannot use)
     never come into play. A material baked with --view-parallax reads the
     picked view node shifted to where its ray meets the eye's at the
     material's fitted depth (_parallax_shift; baker view_parallax.h);
  5. per light (_light), its direction's light factors (resampled densely
     in the pack, so a stochastic bilinear read stands in for clothbake's
     Catmull-Rom), times its irradiance: W_k = sum_l E_l F_k(v, l). A sun's
     E is its input; a point light's over r^2; a spot's that times Cycles'
     cone mask (_spot_mask); an area light is read at two points mirrored
     through its centre, picked at random on its shape (_area_offset), each
     a point light of half its intensity times cos(off its normal);
  6. L = max(0, sum_k C_k W_k) (_components), alpha A; the shaders
     (_shaders). A colour-free material (parts "specular-warp-weft") sums
     its five parts apart, S = sum_k S_k W_k and likewise W, F, Wn, Fn
     (each RGB: W_k is), and L = S + W c_warp + F c_weft + Wn c_warp_next
     + Fn c_weft_next (_coloured), the yarn colours read from the group's
     colour inputs or, per thread, from the colour strips
     (material_colours.py) at the texel step 4 picked (_strip_uv), the
     next colours from the owner + 1 or - 1 strip as the picked view node's
     ray runs (the pack's next atlas holds that side): colours change with
     no rebuild, by the inputs' values and the strips' pixels.
Route "exact": Emission(L) + Transparent(1 - A), the reference renderer's
sum (no shadows from other objects, no cloth-on-cloth shadowing).
Route "cycles-lit": lights on the viewer's side of the surface go through
a Diffuse closure whose colour is pi L_front / (sum_l E_l cos_l + pi W), so
that Cycles (or Eevee) adds its own shadows and the light's live power;
lights behind the surface (light through the cloth) stay Emission. The
world, as a uniform radiance W (the World radiance input), is two more
terms read like a light's (_world): the material's factors integrated over
the viewer's hemisphere into the closure's sum (pi W in its denominator:
Cycles lights the closure with the world itself), over the other into the
Emission.

The footprint: the distance to the camera (the point in camera space) x
the camera's pixel angle (sensor width / lens / pixels, a driver on the
scene's camera and resolution), stretched by 1 / sqrt(cos) of the view's
tilt, in level-0 texels through the world units per UV there: the face's
sqrt(world area / UV area), a FACE attribute Apply writes on the mesh
(clothbake's local frame takes the same geometric mean of the two axes);
where that attribute is missing or 0, the group's World per UV input (the
mean over the evaluated mesh). Divided by sqrt(samples)
(Cycles' samples: each sample prefilters its stratum of the pixel).

Node creation order matters, not only the graph: Cycles compiles nodes in
creation order and keeps a value on its 255-float SVM stack until its last
user, so the steps run in the order above and must not be reordered.
"""
import math
from collections import namedtuple

import bpy

from ..core.material_manifest import HORIZON
from .graph import Graph, SubGraph

GROUP_VERSION = 6
STRETCH_ATTRIBUTE = "clothbake_world_per_uv"   # material_apply writes it
FRAME_SCALE_ATTRIBUTE = "clothbake_frame_scale"  # likewise: (e, 1 / e, depth ratio) per face
PARALLAX_MIN_Z = 0.0174524  # sin(1 deg): view_parallax.h k_parallax_min_z, the bake's horizon clamp
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


def _mix(g, blend, a, b, fac, column):
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


# --- the group's sockets -------------------------------------------------------

def _inputs(group, kinds):
    """The group's inputs. Per light l: its vector (a sun's direction toward
    it, else its position: a spot's apex, an area light's centre), its
    irradiance (colour x power x the watts' factor, 0 when hidden) and the
    point flag; a spot's axis (the way it shines), cos(size / 2) and the
    smoothstep's width on the cosine; an area light's axis (its emitting
    normal), its two sides as world vectors (size x scale along the light's
    X and Y) and the ellipse flag (disk, ellipse)."""
    new = group.inputs.new
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
    new = group.inputs.new
    for family in ("Warp", "Weft"):
        new("NodeSocketColor", f"{family} colour").default_value = (0.5, 0.5, 0.5, 1.0)
    for family in ("Warp", "Weft"):
        s = new("NodeSocketFloat", f"{family} per thread")
        s.default_value, s.min_value, s.max_value = 0.0, 0.0, 1.0


def _new_group(name, key, kinds, strips=None, lit=False):
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    group["clothbake_key"] = key
    _inputs(group, kinds)
    if lit:
        # The world's radiance, uniform (material_drivers.drive_world): the
        # cycles-lit route's world term (_world).
        group.inputs.new("NodeSocketVector", "World radiance")
    if strips is not None:
        _colour_inputs(group)
    group.outputs.new("NodeSocketShader", "Shader")
    group.outputs.new("NodeSocketColor", "Color")
    group.outputs.new("NodeSocketFloat", "Alpha")
    return group


# --- direction maths in nodes (core/directions.py, node for node) --------------

def _local(g, frame, d, column):
    """d in the frame: (d.T, d.B, d.N)."""
    return (g.vmath("DOT_PRODUCT", d, frame.tangent, column=column),
            g.vmath("DOT_PRODUCT", d, frame.bitangent, column=column),
            g.vmath("DOT_PRODUCT", d, frame.normal, column=column))


def _hemi(g, x, y, z, column):
    """The hemi-octahedral (u, v) of (x, y, z)."""
    l1 = g.math("MAXIMUM", g.math("ADD", g.math("ADD", g.math("ABSOLUTE", x, column=column),
                                                g.math("ABSOLUTE", y, column=column),
                                                column=column),
                                  g.math("ABSOLUTE", z, column=column), column=column),
                1e-20, column=column)
    px = g.math("DIVIDE", x, l1, column=column + 1)
    py = g.math("DIVIDE", y, l1, column=column + 1)
    u = g.math("MULTIPLY_ADD", g.math("ADD", px, py, column=column + 1), 0.5, 0.5,
               column=column + 1, clamp=True)
    v = g.math("MULTIPLY_ADD", g.math("SUBTRACT", px, py, column=column + 1), 0.5, 0.5,
               column=column + 1, clamp=True)
    return u, v


def _horizon(g, u, v, column):
    """The horizon warp of the material's light map (directions.horizon_to_grid):
    the diamond's radius rho goes to 1 - sqrt(1 - rho)."""
    a = g.math("MULTIPLY_ADD", u, 2.0, -1.0, column=column)
    b = g.math("MULTIPLY_ADD", v, 2.0, -1.0, column=column)
    px = g.math("MULTIPLY", g.math("ADD", a, b, column=column), 0.5, column=column)
    py = g.math("MULTIPLY", g.math("SUBTRACT", a, b, column=column), 0.5, column=column)
    rho = g.math("ADD", g.math("ABSOLUTE", px, column=column),
                 g.math("ABSOLUTE", py, column=column), column=column)
    warped = g.math("SUBTRACT", 1.0, g.math("SQRT", g.math("SUBTRACT", 1.0, g.math(
        "MINIMUM", rho, 1.0, column=column), column=column, clamp=True), column=column),
        column=column)
    scale = g.math("DIVIDE", warped, g.math("MAXIMUM", rho, 1e-12, column=column),
                   column=column + 1)
    px = g.math("MULTIPLY", px, scale, column=column + 1)
    py = g.math("MULTIPLY", py, scale, column=column + 1)
    return (g.math("MULTIPLY_ADD", g.math("ADD", px, py, column=column + 1), 0.5, 0.5,
                   column=column + 1, clamp=True),
            g.math("MULTIPLY_ADD", g.math("SUBTRACT", px, py, column=column + 1), 0.5, 0.5,
                   column=column + 1, clamp=True))


def _pick(g, coord, nodes, xi, column):
    """Node floor(coord (nodes - 1) + xi), at most nodes - 1: node i0 + 1
    with probability frac, the bilinear weight."""
    return g.math("MINIMUM", g.math("FLOOR", g.math("MULTIPLY_ADD", coord, float(nodes - 1),
                                                    xi, column=column), column=column),
                  float(nodes - 1), column=column)


# --- the steps -------------------------------------------------------------------

def _frame(g, gin):
    """Step 1: the frame (N, T, B) at the shading point.

    The Tangent node (input Tangent) is dP/du with no sign. Input
    Bitangent is a Normal Map node's output (tangent space, the same UV
    map) for the colour (0.5, 1, 0.5): MikkTSpace's signed bitangent,
    along dP/dv, negated on back faces by Cycles and Eevee alike. Its side
    of N x T, unflipped with Backfacing, is the handedness s; B = s N x T.
    Where the UVs run with the face winding s is exactly 1 and B is N x T
    bit for bit; a Normal Map node that finds no tangents returns the
    normal, s = 1 (the old frame)."""
    geo = g.node("ShaderNodeNewGeometry", 0)
    facing = geo.outputs["Normal"]                      # toward the viewer (Cycles flips it)
    flip = g.math("MULTIPLY_ADD", geo.outputs["Backfacing"], -2.0, 1.0, column=1)
    normal = g.scale(facing, flip, 1)                   # the mesh's own side
    t_in = gin["Tangent"]
    tangent = g.vmath("NORMALIZE", g.vmath("SUBTRACT", t_in, g.scale(
        normal, g.vmath("DOT_PRODUCT", normal, t_in, column=1), 1), column=1), column=1)
    cross = g.vmath("CROSS_PRODUCT", normal, tangent, column=2)
    side = g.math("MULTIPLY", g.vmath("DOT_PRODUCT", gin["Bitangent"], cross, column=2), flip,
                  column=2)
    handedness = g.math("MULTIPLY_ADD", g.math("LESS_THAN", side, 0.0, column=2), -2.0, 1.0,
                        column=2)
    bitangent = g.scale(cross, handedness, 2)
    return Frame(geo, facing, normal, tangent, bitangent, _frame_scale(g))


def _frame_scale(g):
    """The per-face factors (sx, sy, sz) that carry (d.T, d.B, d.N) into the
    material's frame where the UV map stretches one way or the depth
    differs from the material's (material_apply.write_face_frame_scale);
    (1, 1, 1) where the attribute is missing or 0."""
    attr = g.node("ShaderNodeAttribute", 1, attribute_type="GEOMETRY",
                  attribute_name=FRAME_SCALE_ATTRIBUTE, label="frame scale, per face")
    sx, sy, sz = g.separate(attr.outputs["Vector"], column=2)
    missing = g.math("LESS_THAN", sz, 1e-12, column=2)
    return tuple(g.math("ADD", c, missing, column=2) for c in (sx, sy, sz))


def _scaled(g, frame, x, y, z, column):
    """(x, y, z) in the frame times the face's factors: the hemi-octahedral
    map divides by the L1 norm, so the product needs no normalising."""
    sx, sy, sz = frame.scale
    return (g.math("MULTIPLY", x, sx, column=column), g.math("MULTIPLY", y, sy, column=column),
            g.math("MULTIPLY", z, sz, column=column))


def _view_direction(g, frame):
    """Step 1: the direction toward the eye in the frame: (z, its side, u, v,
    the material-frame vector (x, y, z) that u, v encode, not normalised)."""
    vx, vy, vz = _local(g, frame, frame.geometry.outputs["Incoming"], 2)
    view_side = g.math("LESS_THAN", vz, 0.0, column=3)
    scaled = _scaled(g, frame, vx, vy, vz, 3)
    vu, vv = _hemi(g, *scaled, 3)
    return vz, view_side, vu, vv, scaled


def _randoms(g, position, area=False):
    """Random numbers per shading point: two White Noise nodes, 7 values
    (xi1..xi7) for the picks of steps 3 to 5; with area lights two more
    (xi8, the second node's unused Value, and xi9 from a third node) pick
    the point on each area light."""
    def noise(offset, column):
        at = g.vmath("ADD", position, offset, column=column)
        n = g.node("ShaderNodeTexWhiteNoise", column, noise_dimensions="3D")
        g.feed(n.inputs["Vector"], at)
        return g.separate(n.outputs["Color"], column=column) + (n.outputs["Value"],)

    xi1, xi2, xi3, xi7 = noise((0.0, 0.0, 0.0), 4)
    xi4, xi5, xi6, xi8 = noise((17.13, -3.71, 9.29), 4)
    if not area:
        return xi1, xi2, xi3, xi4, xi5, xi6, xi7
    at = g.vmath("ADD", position, (-5.37, 11.71, 2.93), column=4)
    n = g.node("ShaderNodeTexWhiteNoise", 4, noise_dimensions="3D")
    g.feed(n.inputs["Vector"], at)
    return xi1, xi2, xi3, xi4, xi5, xi6, xi7, xi8, n.outputs["Value"]


def _view_node(g, k, view_side, vu, vv, xi_i, xi_j):
    """Step 4: the view node (i, side K + j), picked stochastically; and j."""
    vi = _pick(g, vu, k, xi_i, 5)
    vj = _pick(g, vv, k, xi_j, 5)
    view_row = g.math("MULTIPLY_ADD", view_side, float(k), vj, column=6)   # side K + j
    return vi, view_row, vj


def _slope(g, x, y, z, column):
    """view_parallax.h's material_slope of (x, y, z), not normalised:
    (x, y) / max(|z|, sin(1 deg) |(x, y, z)|)."""
    length = g.math("SQRT", g.math("ADD", g.math("MULTIPLY", x, x, column=column), g.math(
        "MULTIPLY_ADD", y, y, g.math("MULTIPLY", z, z, column=column), column=column),
        column=column), column=column)
    den = g.math("MAXIMUM", g.math("ABSOLUTE", z, column=column),
                 g.math("MULTIPLY", length, PARALLAX_MIN_Z, column=column), column=column)
    return (g.math("DIVIDE", x, den, column=column + 1),
            g.math("DIVIDE", y, den, column=column + 1))


def _parallax_shift(g, info, scaled, vi, vj):
    """Step 4b, for a material baked with --view-parallax: where the picked
    view node is read, in repeats added to the UV's: view_parallax.h's
    parallax_shift_mm over repeat_mm, -h / depth_scale (slope(eye) -
    slope(node)), the node's direction decoded from its (i, j) on the
    hemi-octahedral square (only |z| counts, so either side)."""
    k = info.k
    ex, ey = _slope(g, *scaled, 6)
    a = g.math("MULTIPLY_ADD", vi, 2.0 / (k - 1), -1.0, column=6)
    b = g.math("MULTIPLY_ADD", vj, 2.0 / (k - 1), -1.0, column=6)
    px = g.math("MULTIPLY", g.math("ADD", a, b, column=6), 0.5, column=6)
    py = g.math("MULTIPLY", g.math("SUBTRACT", a, b, column=6), 0.5, column=6)
    pz = g.math("MAXIMUM", g.math("SUBTRACT", g.math("SUBTRACT", 1.0, g.math(
        "ABSOLUTE", px, column=6), column=6), g.math("ABSOLUTE", py, column=6), column=6), 0.0,
        column=6)
    nx, ny = _slope(g, px, py, pz, 7)
    factor = -info.parallax_depth_mm / info.depth_scale
    du = g.math("MULTIPLY", g.math("SUBTRACT", ex, nx, column=8),
                factor / info.repeat_mm[0], column=8)
    dv = g.math("MULTIPLY", g.math("SUBTRACT", ey, ny, column=8),
                factor / info.repeat_mm[1], column=8)
    return du, dv


def _level(g, gin, info, position, vz, xi):
    """Step 3: the level from the footprint, picked stochastically between
    the two around it; returns (S_L, P_L across, Y_L, L, P_L up) of the
    pack's layout (the pitches differ for a material addressed per
    crossing: its tiles hold bx x by blocks)."""
    k, r = info.k, info.texels
    bx, by = info.block_grid
    per_repeat = r * info.threads_per_repeat[0]   # level-0 texels per repeat along x
    cam_point = g.node("ShaderNodeVectorTransform", 4, vector_type="POINT",
                       convert_from="WORLD", convert_to="CAMERA")
    g.feed(cam_point.inputs["Vector"], position)
    distance = g.vmath("LENGTH", cam_point.outputs["Vector"], column=5)
    cos_view = g.math("MAXIMUM", g.math("ABSOLUTE", vz, column=5), 0.02, column=5)
    # World units per UV here: the face's own (the mesh attribute Apply
    # writes), else (0: no attribute, or a face without UV area) the input.
    local = g.node("ShaderNodeAttribute", 4, attribute_type="GEOMETRY",
                   attribute_name=STRETCH_ATTRIBUTE, label="world per UV, per face")
    missing = g.math("LESS_THAN", local.outputs["Fac"], 1e-12, column=5)
    world_per_uv = g.math("MULTIPLY_ADD", missing, gin["World per UV"], local.outputs["Fac"],
                          column=5)
    texels_per_world = g.math("DIVIDE", g.math("MULTIPLY", gin["Repeats per UV"],
                                               float(per_repeat), column=5), world_per_uv,
                              column=5)
    footprint = g.math("MULTIPLY", g.math("MULTIPLY", distance, gin["Pixel angle"], column=6),
                       texels_per_world, column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", cos_view, column=6), column=6)
    footprint = g.math("DIVIDE", footprint, g.math("SQRT", g.math("MAXIMUM", gin["Samples"], 1.0,
                                                                  column=6), column=6), column=6)
    footprint = g.math("MULTIPLY", footprint, gin["Footprint scale"], column=7)
    level = g.math("MINIMUM", g.math("LOGARITHM", g.math("MAXIMUM", footprint, 1.0, column=7), 2.0,
                                     column=7), float(info.levels - 1), column=7)
    level = g.math("MINIMUM", g.math("FLOOR", g.math("ADD", level, xi, column=8), column=8),
                   float(info.levels - 1), column=8)
    half_pow = g.math("POWER", 0.5, level, column=8)
    side_texels = g.math("MULTIPLY", half_pow, float(r), column=9)           # S_L
    pitch = g.math("ADD", side_texels, 2.0, column=9) if bx == 1 else \
        g.math("MULTIPLY_ADD", side_texels, float(bx), 2.0, column=9)        # P_L across
    pitch_up = pitch if by == bx else \
        g.math("MULTIPLY_ADD", side_texels, float(by), 2.0, column=9)        # P_L up
    y_level = g.math("MULTIPLY", g.math("ADD", g.math("MULTIPLY", g.math(
        "SUBTRACT", 1.0, half_pow, column=9), 2.0 * r * by, column=9), g.math(
        "MULTIPLY", level, 2.0, column=9), column=9), 2.0 * k, column=10)   # Y_L
    return side_texels, pitch, y_level, level, pitch_up


def _repeat_coords(g, gin, shift):
    """The UV map in repeats (x, y), shifted by the view node's parallax
    (_parallax_shift, in repeats) when `shift` is not None."""
    ux, uy, _ = g.separate(g.scale(gin["UV"], gin["Repeats per UV"], 6), 7)
    if shift is not None:
        ux = g.math("ADD", ux, shift[0], column=7)
        uy = g.math("ADD", uy, shift[1], column=7)
    return ux, uy


def _tile_uv(g, pack, view, level, tx, ty, k):
    """Step 4: the pack's UV of component 0's pixel (tx, ty) in the view
    node's tile on the level, and the step to component k: + (k % per_row)
    K P_L across and (k // per_row) bands up."""
    vi, view_row = view
    _, pitch, y_level, _, pitch_up = level
    px0 = g.math("MULTIPLY_ADD", vi, pitch, tx, column=11)
    py0 = g.math("ADD", g.math("MULTIPLY_ADD", view_row, pitch_up, ty, column=11), y_level,
                 column=11)
    uv0 = g.combine(g.math("DIVIDE", px0, float(pack.width), column=12),
                    g.math("DIVIDE", py0, float(pack.height), column=12), 0.0, column=12)
    step = g.combine(g.math("MULTIPLY", pitch, float(k) / pack.width, column=12),
                     float(pack.band) / pack.height, 0.0, column=12)
    return uv0, step


def _texel_address(g, gin, pack, k, view, level, xi_x, xi_y, shift=None):
    """Steps 2 and 4: the texel (periodic, stochastic bilinear) and the
    address of component 0's tile; returns (uv0, the step to component k,
    Texel: where the pick landed, for the colour strips). `shift`: the view
    node's parallax shift in repeats (_parallax_shift), or None."""
    side_texels, _, _, level_index, _ = level
    ux, uy = _repeat_coords(g, gin, shift)

    def texel(coord, xi, column):
        t = g.math("MULTIPLY", g.math("FRACT", coord, column=column), side_texels, column=column)
        # pixel centre of texel floor(t - 0.5 + xi), one past the gutter
        return g.math("ADD", g.math("FLOOR", g.math("ADD", t, g.math("SUBTRACT", xi, 0.5,
                                                                     column=column),
                                                    column=column), column=column), 1.5,
                      column=column)

    tx = texel(ux, xi_x, 10)
    ty = texel(uy, xi_y, 10)
    uv0, step = _tile_uv(g, pack, view, level, tx, ty, k)
    return uv0, step, Texel(ux, uy, tx, ty, side_texels, level_index)


def _crossing_address(g, gin, info, pack, view, level, xi_x, xi_y, index_image, shift=None,
                      span_image=None):
    """Steps 2 and 4 for a material addressed per crossing
    (docs/material-format.md, "Addressed per crossing"): every crossing
    spans S_L texels whatever its width, the stochastic bilinear pick is a
    tap counted in crossings and texels over all repeats, and the tap's
    crossing (wrapped into the repeat) reads its block from the index image
    (the pack's crossings.exr: block, its column and row in the tile's grid
    of blocks). Returns (uv0, the step to component k, the taps' crossings
    over all repeats (end, pick): the threads whose colours they take).
    The crossing coordinate over all repeats: for evenly spaced threads
    n u - offset, offset the first thread's centre over its pitch less 1/2
    (its span starts half a pitch before it); otherwise n floor(u) + e +
    (fract(u) - start) / span, (e, start, 1 / span) read from the pack's
    span image at fract(u) (material_pack.span_pixels)."""
    side_texels = level[0]
    ux, uy = _repeat_coords(g, gin, shift)

    def tap(coord, axis, xi, column):
        n = (info.ends, info.picks)[axis]
        centres = info.centres_mm[("warp", "weft")[axis]]
        if info.even[axis]:
            offset = centres[0] / (info.repeat_mm[axis] / n) - 0.5
            crossings = g.math("MULTIPLY_ADD", coord, float(n), -offset, column=column)
        else:
            whole = g.math("FLOOR", coord, column=column)
            part = g.math("SUBTRACT", coord, whole, column=column)
            at = g.combine(part, 0.25 + 0.5 * axis, 0.0, column=column)
            span = g.node("ShaderNodeTexImage", column, image=span_image,
                          interpolation="Closest", extension="EXTEND",
                          label=f"{('warp', 'weft')[axis]} spans")
            g.feed(span.inputs["Vector"], at)
            e, start, inv = g.separate(span.outputs["Color"], column=column)
            crossings = g.math("MULTIPLY_ADD", g.math("SUBTRACT", part, start, column=column),
                               inv, g.math("MULTIPLY_ADD", whole, float(n), e, column=column),
                               column=column)
        t = g.math("FLOOR", g.math("MULTIPLY_ADD", crossings, side_texels, g.math(
            "SUBTRACT", xi, 0.5, column=column), column=column), column=column)
        crossing = g.math("FLOOR", g.math("DIVIDE", t, side_texels, column=column),
                          column=column)
        local = g.math("SUBTRACT", t, g.math("MULTIPLY", crossing, side_texels, column=column),
                       column=column)
        wrapped = g.math("WRAP", crossing, float(n), 0.0, column=column)
        at = g.math("MULTIPLY_ADD", wrapped, 1.0 / n, 0.5 / n, column=column)
        return crossing, local, at

    end, lx, at_x = tap(ux, 0, xi_x, 10)
    pick, ly, at_y = tap(uy, 1, xi_y, 10)
    at = g.combine(at_x, at_y, 0.0, column=11)
    index = g.node("ShaderNodeTexImage", 11, image=index_image, interpolation="Closest",
                   extension="EXTEND", label="crossing's block")
    g.feed(index.inputs["Vector"], at)
    _, block_x, block_y = g.separate(index.outputs["Color"], column=11)
    # the picked texel's pixel centre in its tile, one past the gutter
    tx = g.math("ADD", g.math("MULTIPLY_ADD", block_x, side_texels, lx, column=11), 1.5,
                column=11)
    ty = g.math("ADD", g.math("MULTIPLY_ADD", block_y, side_texels, ly, column=11), 1.5,
                column=11)
    uv0, step = _tile_uv(g, pack, view, level, tx, ty, info.k)
    return uv0, step, (end, pick)


def _spot_mask(g, gin, l, direction, col):
    """Cycles 3.x's spot attenuation (measured in Blender 3.4: it holds the
    cosine itself): a = cos(angle between the light's axis and the way to
    the point), a x smoothstep((a - cos(size / 2)) / smooth), 0 outside the
    cone; smooth = (1 - cos(size / 2)) x blend, 0 for a hard edge."""
    a = g.math("MULTIPLY", g.vmath("DOT_PRODUCT", direction, gin[f"Light {l} axis"],
                                   column=col), -1.0, column=col)
    t = g.math("DIVIDE", g.math("SUBTRACT", a, gin[f"Light {l} cos half angle"], column=col),
               g.math("MAXIMUM", gin[f"Light {l} smooth"], 1e-9, column=col), column=col,
               clamp=True)
    smooth = g.math("MULTIPLY", g.math("MULTIPLY", t, t, column=col),
                    g.math("MULTIPLY_ADD", t, -2.0, 3.0, column=col), column=col)
    return g.math("MULTIPLY", a, smooth, column=col)


def _area_offset(g, gin, l, xis, col):
    """A point on area light l, uniform over its shape, from two random
    numbers (shifted per light), as its offset from the centre: su U + sv V
    with U, V its sides; (su, sv) in the square [-1/2, 1/2]^2, or in the
    disk of radius 1/2 (r = sqrt(xi) / 2, angle 2 pi xi') when the ellipse
    flag is 1. The pixel's samples hit other points, so they integrate the
    light."""
    xa = g.math("FRACT", g.math("ADD", xis[0], (0.6180339887 * l) % 1.0, column=col), column=col)
    xb = g.math("FRACT", g.math("ADD", xis[1], (0.4142135624 * l) % 1.0, column=col), column=col)
    r = g.math("MULTIPLY", g.math("SQRT", xa, column=col), 0.5, column=col)
    phi = g.math("MULTIPLY", xb, 2.0 * math.pi, column=col)
    ellipse = gin[f"Light {l} ellipse"]
    su = g.lerp(g.math("SUBTRACT", xa, 0.5, column=col), g.math(
        "MULTIPLY", r, g.math("COSINE", phi, column=col), column=col), ellipse, col)
    sv = g.lerp(g.math("SUBTRACT", xb, 0.5, column=col), g.math(
        "MULTIPLY", r, g.math("SINE", phi, column=col), column=col), ellipse, col)
    on_u = g.scale(gin[f"Light {l} side u"], su, col)
    on_v = g.scale(gin[f"Light {l} side v"], sv, col)
    return g.vmath("ADD", on_u, on_v, column=col)


def _light_at(g, gin, l, kind, position, target, col):
    """The unit direction toward light l and the factor its irradiance input
    is scaled by at the point: a sun's 1; a point light's 1 / r^2; a spot's
    1 / r^2 x its cone's attenuation; an area light's cos(off its normal) /
    r^2 toward `target`, a point on it (0 behind it: one-sided), whose
    irradiance input is its radiant intensity along the normal."""
    vec, is_point = gin[f"Light {l} vector"], gin[f"Light {l} point"]
    if kind in ("SUN", "POINT"):
        to_point = g.vmath("SUBTRACT", vec, position, column=col)
        direction = g.vmath("NORMALIZE", g.vmath("ADD", vec, g.scale(g.vmath(
            "SUBTRACT", to_point, vec, column=col), is_point, col), column=col), column=col)
        r2 = g.math("MAXIMUM", g.vmath("DOT_PRODUCT", to_point, to_point, column=col), 1e-12,
                    column=col)
        atten = g.math("ADD", g.math("MULTIPLY", is_point, g.math("SUBTRACT", g.math(
            "DIVIDE", 1.0, r2, column=col), 1.0, column=col), column=col), 1.0, column=col)
        return direction, atten
    to_point = g.vmath("SUBTRACT", vec if kind == "SPOT" else target, position, column=col)
    direction = g.vmath("NORMALIZE", to_point, column=col)
    inv_r2 = g.math("DIVIDE", 1.0, g.math("MAXIMUM", g.vmath(
        "DOT_PRODUCT", to_point, to_point, column=col), 1e-12, column=col), column=col)
    if kind == "SPOT":
        return direction, g.math("MULTIPLY", inv_r2, _spot_mask(g, gin, l, direction, col),
                                 column=col)
    cos_light = g.math("MAXIMUM", g.math("MULTIPLY", g.vmath(
        "DOT_PRODUCT", direction, gin[f"Light {l} axis"], column=col), -1.0, column=col), 0.0,
        column=col)
    return direction, g.math("MULTIPLY", inv_r2, cos_light, column=col)


def _light(g, gin, l, kind, frame, position, view, light_map, pack, lit, xis, col,
           target=None, weight=1.0):
    """Step 5 for light l (for an area light, the point `target` on it,
    `weight` its share): its direction and irradiance at the point and its
    light factors' address. Returns (LightTerm, the cycles-lit
    denominator's term E cos, or None on route exact)."""
    vi, view_row = view
    m = pack.dense
    q = m + 2
    irr = gin[f"Light {l} irradiance"]
    direction, atten = _light_at(g, gin, l, kind, position, target, col)
    if weight != 1.0:
        atten = g.math("MULTIPLY", atten, weight, column=col)
    irradiance = _mix(g, "ADD", BLACK, irr, atten, col)
    lx, ly, lz = _local(g, frame, direction, col + 1)
    light_side = g.math("LESS_THAN", lz, 0.0, column=col + 1)
    lu, lv = _hemi(g, *_scaled(g, frame, lx, ly, lz, col + 1), col + 1)
    if light_map == HORIZON:
        lu, lv = _horizon(g, lu, lv, col + 2)
    la = _pick(g, lu, m, xis[0], col + 3)
    lb = _pick(g, lv, m, xis[1], col + 3)
    # tile of (view_side, i, j), group 0, light side; pixel centre of (a, b)
    lpx = g.math("ADD", g.math("MULTIPLY", g.math("MULTIPLY_ADD", vi, 2.0, light_side,
                                                  column=col + 4), float(q), column=col + 4),
                 g.math("ADD", la, 1.5, column=col + 4), column=col + 4)
    lpy = g.math("ADD", g.math("MULTIPLY", view_row, float(q), column=col + 4),
                 g.math("ADD", lb, 1.5, column=col + 4), column=col + 4)
    luv = g.combine(g.math("DIVIDE", lpx, float(pack.light_width), column=col + 5),
                    g.math("DIVIDE", lpy, float(pack.light_height), column=col + 5), 0.0,
                    column=col + 5)
    if not lit:
        return LightTerm(luv, [(irradiance, 0)]), None
    cos_l = g.vmath("DOT_PRODUCT", direction, frame.facing, column=col + 5)
    front = g.math("GREATER_THAN", cos_l, 0.0, column=col + 5)
    e_front = _mix(g, "ADD", BLACK, irradiance, front, col + 5)
    e_back = _mix(g, "SUBTRACT", irradiance, e_front, 1.0, col + 5)
    term = _mix(g, "ADD", BLACK, e_front, g.math("MAXIMUM", cos_l, 0.0, column=col + 5), col + 5)
    return LightTerm(luv, [(e_front, 0), (e_back, 1)]), term


def _lights(g, gin, frame, position, view, info, pack, kinds, lit, xis, col):
    """Step 5 for every light: ([LightTerm], cycles-lit denominator or
    None, the next free column)."""
    per_light, denom = [], None
    for l, kind in enumerate(kinds):
        targets = [None]
        if kind == "AREA":
            # Two points on it, mirrored through its centre (antithetic:
            # the light's fall-off across it cancels to first order), each
            # weighted 1/2.
            offset = _area_offset(g, gin, l, xis[2:], col)
            centre = gin[f"Light {l} vector"]
            targets = [g.vmath("ADD", centre, offset, column=col),
                       g.vmath("SUBTRACT", centre, offset, column=col)]
        for target in targets:
            light, term = _light(g, gin, l, kind, frame, position, view, info.light_map, pack,
                                 lit, xis, col, target=target, weight=1.0 / len(targets))
            per_light.append(light)
            if term is not None:
                denom = term if denom is None else _mix(g, "ADD", denom, term, 1.0, col + 6)
            col += 7
    return per_light, denom, col


def _world(g, gin, view, pack, k, col):
    """Step 5 for the world, on the cycles-lit route: a uniform world of
    radiance W adds W sum_k C_k G_k(v), G the light factors integrated over
    a hemisphere (material_pack's world factors), G over the viewer's
    hemisphere into the front sum (so the Diffuse closure, lit by Cycles'
    own world, carries it) and over the other into the sum from behind.
    Two LightTerms, read like a light's factors at the picked view node;
    and the cycles-lit denominator's world term pi W, the irradiance a
    uniform world gives a Lambertian closure over its open hemisphere.
    Returns ([LightTerm front, LightTerm behind], pi W)."""
    vi, view_row = view
    q = pack.dense + 2
    x = g.math("MULTIPLY_ADD", vi, 2.0 * q, 1.5, column=col)           # pixel centre, ws = 0
    y = g.math("ADD", view_row, 2.0 * k * q + 0.5, column=col)
    u = g.math("DIVIDE", x, float(pack.light_width), column=col)
    v = g.math("DIVIDE", y, float(pack.light_height), column=col)
    front = g.combine(u, v, 0.0, column=col)
    behind = g.combine(g.math("ADD", u, float(q) / pack.light_width, column=col), v, 0.0,
                       column=col)
    radiance = g.ready(gin["World radiance"], "RGBA")
    return [LightTerm(front, [(radiance, 0)]), LightTerm(behind, [(radiance, 1)])], \
        _mix(g, "ADD", BLACK, radiance, math.pi, col)


def _factor_reads(g, gi, per_light, light_image, k, pack, col, gate=None):
    """Each light's factors of components 4 gi .. 4 gi + 3: (R, G, B, A);
    the addresses times `gate` (_gated: exactly 1) when there is one."""
    q = pack.dense + 2
    factors = []
    for l, light in enumerate(per_light):
        offset = (gi * 2.0 * k * q / pack.light_width, 0.0, 0.0)
        if gate is None:
            at = g.vmath("ADD", light.uv, offset, column=col)
        else:
            uv = g.ready(light.uv, "VECTOR")
            n = g.node("ShaderNodeVectorMath", col, operation="MULTIPLY_ADD")
            g.feed(n.inputs[0], uv)
            g.feed(n.inputs[1], gate)
            g.feed(n.inputs[2], offset)
            at = n.outputs["Vector"]
        tex = g.node("ShaderNodeTexImage", col, image=light_image,
                     interpolation="Closest", extension="EXTEND",
                     label=f"light {l} factors {4 * gi}..{4 * gi + 3}")
        g.feed(tex.inputs["Vector"], at)
        r, gg, b = g.separate(tex.outputs["Color"], column=col + 1)
        factors.append((r, gg, b, tex.outputs["Alpha"]))
    return factors


def _component(g, kk, c, coeff_image, address, per_light, factors, sums, pack, col,
               next_image=None):
    """Component kk (channel c of its group's factors): its coefficients
    read, times each light's W_k, added into `sums`. Colour-free (a
    `next_image`): each of the five parts S, W, F (the coefficients' RGB)
    and Wn, Fn (the next atlas's R, G) times W_k into its own sum, [S, W,
    F, Wn, Fn] per accumulator. Returns the read's alpha output (and, when
    colour-free, the next atlas's sides: plus_x, plus_y)."""
    uv0, step = address[:2]
    where = uv0
    if kk:
        n = g.node("ShaderNodeVectorMath", col + 2, operation="MULTIPLY_ADD")
        g.feed(n.inputs[0], step)
        g.feed(n.inputs[1], (float(kk % pack.per_row), float(kk // pack.per_row), 0.0))
        g.feed(n.inputs[2], uv0)
        where = n.outputs["Vector"]
    tex = g.node("ShaderNodeTexImage", col + 3, image=coeff_image,
                 interpolation="Closest", extension="EXTEND", label=f"component {kk}")
    g.feed(tex.inputs["Vector"], where)
    weights = [None, None]
    for light, f in zip(per_light, factors):
        for e, which in light.parts:
            weights[which] = _mix(g, "ADD", weights[which] or BLACK, e, f[c], col + 4)
    if next_image is not None:
        nxt = g.node("ShaderNodeTexImage", col + 3, image=next_image,
                     interpolation="Closest", extension="EXTEND", label=f"component {kk} next")
        g.feed(nxt.inputs["Vector"], where)
        s_, w_, f_ = g.separate(tex.outputs["Color"], column=col + 4)
        wn, fn, plus_x = g.separate(nxt.outputs["Color"], column=col + 4)
        for which in (0, 1):
            if weights[which] is not None:
                acc = sums[which] or [BLACK] * 5
                sums[which] = [_mix(g, "ADD", a, weights[which], p, col + 5)
                               for a, p in zip(acc, (s_, w_, f_, wn, fn))]
        return tex.outputs["Alpha"], (plus_x, nxt.outputs["Alpha"])
    for which in (0, 1):
        if weights[which] is not None:
            term = _mix(g, "MULTIPLY", tex.outputs["Color"], weights[which], 1.0, col + 5)
            sums[which] = term if sums[which] is None else \
                _mix(g, "ADD", sums[which], term, 1.0, col + 5)
    return tex.outputs["Alpha"]


def _gated(g, last, address):
    """The group's texture coordinates (the address's uv0 and step; the
    factor reads take the gate as a vector, _factor_reads) times a gate
    that is exactly 1 but is read from
    `last`, the previous group's last coefficient read (1 - (a < -3e38):
    1 for any alpha, NaN included). Why: Cycles makes the conversion of a
    texture read's coordinates (a vector into the read's point socket)
    after every node of the sub-group, so each read waits a compile pass;
    ungated, every group's coordinates were computed in that pass and held
    on the SVM stack together (3 floats per read: 24 reads and three
    lights overflowed it). Gated, a group's coordinates are computed once
    the previous group's reads are done."""
    gate = g.math("MULTIPLY_ADD", g.math("LESS_THAN", last, -3e38, column=0), -1.0, 1.0,
                  column=0)
    uv0, step = address[:2]
    return ((g.scale(uv0, gate, 0), g.scale(step, gate, 0)) + tuple(address[2:]),
            g.scale((1.0, 1.0, 1.0), gate, 0))


def _components(g, images, address, per_light, k, pack, col):
    """Step 6: per group of four components, each light's factors, then the
    four coefficients, summed at once. Nodes are made in this order because
    Cycles compiles them in creation order and keeps a value on its SVM
    stack (255 floats) until its last user: all W_k first, then all C_k,
    overflowed the stack at rank 24 on the cycles-lit route ("out of SVM
    stack space": a black cloth). Returns ([radiance (front when lit),
    radiance from behind], alpha, the next free column); colour-free
    (images holding a third, the next atlas): ([[S, W, F, Wn, Fn] per
    accumulator], alpha, the column, (plus_x, plus_y))."""
    coeff_image, light_image = images[:2]
    next_image = images[2] if len(images) > 2 else None
    sums = [None, None]
    alpha = sides = last = None
    for gi in range(pack.groups):
        # Each group of four in a sub-group of its own (graph.SubGraph: the
        # build's cost), made where its nodes stood, so the order holds.
        sub = SubGraph(g, f".{g.tree.name} components {4 * gi}-{4 * gi + 3}", col)
        group_address, gate = address, None
        if last is not None:
            group_address, gate = _gated(sub, last, address)
        firsts, spare = [], []
        factors = _factor_reads(sub, gi, per_light, light_image, k, pack, 0, gate)
        for c in range(4):
            kk = 4 * gi + c
            if kk >= pack.rank:
                break
            a = _component(sub, kk, c, coeff_image, group_address, per_light, factors, sums,
                           pack, 0, next_image)
            if next_image is not None:
                a, side = a
                if kk == 0:
                    firsts += list(side)
                else:
                    spare.append(side[0])
            if kk == 0:
                firsts.insert(0, a)
            read_alpha = a
        # The next gate's source: the last read's alpha, and the next
        # atlas's plus_x of components past 0 (a copy of component 0's):
        # Cycles' Separate Color keeps an output nobody reads on the SVM stack
        # to the end, so each is read here (min), 1 float a component.
        for plus in spare:
            read_alpha = sub.math("MINIMUM", read_alpha, plus, column=0)
        flat = [s for acc in sums if acc is not None for s in (acc if isinstance(acc, list) else [acc])]
        outs = sub.finish(flat + firsts + [read_alpha])
        it = iter(outs)
        sums = [None if acc is None else ([next(it) for _ in acc] if isinstance(acc, list)
                                          else next(it)) for acc in sums]
        if firsts:
            alpha = next(it)
            if next_image is not None:
                sides = (next(it), next(it))
        last = next(it)
        col += 6
    if next_image is not None:
        return sums, alpha, col, sides
    return sums, alpha, col


def _strip_rows(g, coord, t_pixel, texel, q, width, rows, col):
    """The picked texel's place in its family's strips: the column c over
    the q repeats (texel i = t_pixel - 1.5 in -1 .. S_L of repeat
    floor(coord) mod q, wrapped into 0 .. q S_L - 1: periodic), as the
    pixel column c mod W and the row L R + c // W of the own block. The
    same texel as the coefficients, so each pick's colour goes with its
    coefficients."""
    i = g.math("SUBTRACT", t_pixel, 1.5, column=col)
    if q > 1:
        whole = g.math("FLOOR", coord, column=col)
        rep = g.math("WRAP", whole, float(q), 0.0, column=col)
        i = g.math("MULTIPLY_ADD", rep, texel.side_texels, i, column=col)
    columns = g.math("MULTIPLY", texel.side_texels, float(q), column=col)
    column = g.math("WRAP", i, columns, 0.0, column=col)
    row = g.math("MULTIPLY", texel.level, float(rows), column=col)
    if rows > 1:
        row = g.math("ADD", row, g.math("FLOOR", g.math("DIVIDE", column, float(width),
                                                        column=col), column=col), column=col)
        column = g.math("WRAP", column, float(width), 0.0, column=col)
    return column, row


def _thread_places(g, crossings, strips, info, col):
    """(column, own row) of the warp strips and the weft's for a material
    addressed per crossing: its strips hold one column a thread over the
    colours' repeat (material_colours.make_strips) and one level, so a
    tap's column is its end (pick) over all repeats, wrapped into q n."""
    out = []
    for c, n, q, width, rows in ((crossings[0], info.ends, strips.q_warp, strips.warp.size[0],
                                  strips.rows_warp),
                                 (crossings[1], info.picks, strips.q_weft, strips.weft.size[0],
                                  strips.rows_weft)):
        column = g.math("WRAP", c, float(q * n), 0.0, column=col)
        row = 0.0
        if rows > 1:
            row = g.math("FLOOR", g.math("DIVIDE", column, float(width), column=col), column=col)
            column = g.math("WRAP", column, float(width), 0.0, column=col)
        out.append((column, row))
        col += 1
    return tuple(out)


def _strip_places(g, texel, strips, col):
    """(column, own row) of the warp strips (along x) and the weft's (y)."""
    return (_strip_rows(g, texel.ux, texel.tx, texel, strips.q_warp, strips.warp.size[0],
                        strips.rows_warp, col),
            _strip_rows(g, texel.uy, texel.ty, texel, strips.q_weft, strips.weft.size[0],
                        strips.rows_weft, col + 1))


def _yarn_colours(g, gin, family, place, plus, image, rows, levels, col):
    """The family's own and next colours at the pick: its strips' (own
    block; plus block 1 where the ray runs toward +, minus block 2), or the
    family's colour input where its per-thread flag is 0."""
    column, row = place
    width, height = image.size
    u = g.math("DIVIDE", g.math("ADD", column, 0.5, column=col), float(width), column=col)
    block = g.math("MULTIPLY", g.math("SUBTRACT", 2.0, plus, column=col), float(levels * rows),
                   column=col)
    out = []
    for label, r in (("own", row), ("next", g.math("ADD", row, block, column=col))):
        v = g.math("DIVIDE", g.math("ADD", r, 0.5, column=col), float(height), column=col)
        at = g.combine(u, v, 0.0, column=col)
        tex = g.node("ShaderNodeTexImage", col + 1, image=image, interpolation="Closest",
                     extension="EXTEND", label=f"{family} colours, {label}")
        g.feed(tex.inputs["Vector"], at)
        out.append(_mix(g, "MIX", gin[f"{family} colour"], tex.outputs["Color"],
                        gin[f"{family} per thread"], col + 2))
    return out


def _coloured(g, gin, sums, places, sides, strips, levels, col):
    """Colour-free sums [S, W, F, Wn, Fn] per accumulator into radiance:
    S + W c_warp + F c_weft + Wn c_warp_next + Fn c_weft_next
    (docs/material-format.md), channel by channel, so a coloured light's
    W_k stays RGB throughout."""
    warp, warp_next = _yarn_colours(g, gin, "Warp", places[0], sides[0], strips.warp,
                                    strips.rows_warp, levels, col)
    weft, weft_next = _yarn_colours(g, gin, "Weft", places[1], sides[1], strips.weft,
                                    strips.rows_weft, levels, col)
    out = []
    for acc in sums:
        if acc is None:
            out.append(None)
            continue
        rgb = acc[0]
        for part, colour in zip(acc[1:], (warp, weft, warp_next, weft_next)):
            rgb = _mix(g, "ADD", rgb, _mix(g, "MULTIPLY", part, colour, 1.0, col + 3), 1.0,
                       col + 4)
        out.append(rgb)
    return out


def _shaders(g, sums, alpha, denom, lit, col):
    """Step 6's closures into the group's outputs: Emission (+ Diffuse when
    lit) + Transparent(1 - A); Color the radiance, Alpha A. Every value
    first, then the closures, then the output (graph.Graph: creation
    order)."""
    radiance, radiance_back = sums
    zero = (0.0, 0.0, 0.0)
    front = radiance if radiance is not None else zero
    back = radiance_back if radiance_back is not None else zero
    if lit and radiance is not None and radiance_back is not None:
        # Cycles compiles the Diffuse closure's inputs, then the Emission's:
        # whatever both sums read (every coefficient) would wait on the SVM
        # stack between the two. max(f, min(b, 0)) makes the front sum read
        # the back one, so the Diffuse's inputs compute both, and the
        # max(., 0) below makes it max(f, 0) exactly.
        front = g.vmath("MAXIMUM", front, g.vmath("MINIMUM", back, zero, column=col + 4),
                        column=col + 4)
    radiance = g.vmath("MAXIMUM", front, zero, column=col + 4)
    transparency = g.ready(g.math("SUBTRACT", 1.0, alpha, column=col + 5, clamp=True), "RGBA")
    if lit:
        radiance_back = g.vmath("MAXIMUM", back, zero, column=col + 4)
        safe = g.vmath("MAXIMUM", denom if denom is not None else zero, (1e-6,) * 3,
                       column=col + 4)
        colour = g.ready(g.scale(g.vmath("DIVIDE", radiance, safe, column=col + 5), math.pi,
                                 col + 5), "RGBA")
        emitted = g.ready(radiance_back, "RGBA")
        color_out = g.ready(g.vmath("ADD", radiance, radiance_back, column=col + 5), "RGBA")
        diffuse = g.node("ShaderNodeBsdfDiffuse", col + 6)
        g.feed(diffuse.inputs["Color"], colour)
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], emitted)
        add1 = g.node("ShaderNodeAddShader", col + 7)
        g.feed(add1.inputs[0], diffuse.outputs[0])
        g.feed(add1.inputs[1], emission.outputs[0])
    else:
        color_out = g.ready(radiance, "RGBA")
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], color_out)
        add1 = emission
    transparent = g.node("ShaderNodeBsdfTransparent", col + 6)
    g.feed(transparent.inputs["Color"], transparency)
    add = g.node("ShaderNodeAddShader", col + 7)
    g.feed(add.inputs[0], add1.outputs[0])
    g.feed(add.inputs[1], transparent.outputs[0])
    out = g.node("NodeGroupOutput", col + 8)
    g.feed(out.inputs["Shader"], add.outputs[0])
    g.feed(out.inputs["Color"], color_out)
    g.feed(out.inputs["Alpha"], alpha)


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
    group = _new_group(name, key, kinds, strips, lit)
    g = Graph(group)
    gin = g.node("NodeGroupInput", 0).outputs
    frame = _frame(g, gin)
    position = frame.geometry.outputs["Position"]
    vz, view_side, vu, vv, scaled = _view_direction(g, frame)
    xis = _randoms(g, position, area="AREA" in kinds)
    xi1, xi2, xi3, xi4, xi5, xi6, xi7 = xis[:7]
    vi, view_row, vj = _view_node(g, info.k, view_side, vu, vv, xi1, xi2)
    view = (vi, view_row)
    shift = _parallax_shift(g, info, scaled, vi, vj) if info.parallax_depth_mm > 0 else None
    level = _level(g, gin, info, position, vz, xi3)
    if index_image is not None:
        address = _crossing_address(g, gin, info, pack, view, level, xi4, xi5, index_image,
                                    shift, span_image)
        places = _thread_places(g, address[2], strips, info, 12)
        strip_levels = 1
    else:
        address = _texel_address(g, gin, pack, info.k, view, level, xi4, xi5, shift)
        places = None if strips is None else _strip_places(g, address[2], strips, 12)
        strip_levels = info.levels
    per_light, denom, col = _lights(g, gin, frame, position, view, info, pack, kinds, lit,
                                    (xi6, xi7) + tuple(xis[7:]), 13)
    if lit:
        world, world_denom = _world(g, gin, view, pack, info.k, col)
        per_light += world
        denom = world_denom if denom is None else _mix(g, "ADD", denom, world_denom, 1.0, col)
        col += 1
    if strips is None:
        sums, alpha, col = _components(g, (coeff_image, light_image), address, per_light,
                                       info.k, pack, col)
    else:
        sums, alpha, col, sides = _components(g, (coeff_image, light_image, next_image),
                                              address, per_light, info.k, pack, col)
        sums = _coloured(g, gin, sums, places, sides, strips, strip_levels, col)
        col += 5
    _shaders(g, sums, alpha, denom, lit, col)
    if g.late:
        bpy.data.node_groups.remove(group)
        raise RuntimeError(f"clothbake: node group '{name}' links out of creation order (a "
                           f"defect: Cycles would hold values on its SVM stack): {g.late[:5]}")
    _replace_old(name, group)
    return group
