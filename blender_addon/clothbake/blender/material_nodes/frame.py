"""Step 1: the shading frame (N, T, B) and the direction toward the eye in
it."""
from .common import FRAME_SCALE_ATTRIBUTE, Frame
from .directions import hemi_octahedral, to_frame


def shading_frame(g, gin):
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


def frame_scaled(g, frame, x, y, z, column):
    """(x, y, z) in the frame times the face's factors: the hemi-octahedral
    map divides by the L1 norm, so the product needs no normalising."""
    sx, sy, sz = frame.scale
    return (g.math("MULTIPLY", x, sx, column=column), g.math("MULTIPLY", y, sy, column=column),
            g.math("MULTIPLY", z, sz, column=column))


def view_direction(g, frame):
    """Step 1: the direction toward the eye in the frame: (z, its side, u, v,
    the material-frame vector (x, y, z) that u, v encode, not normalised)."""
    vx, vy, vz = to_frame(g, frame, frame.geometry.outputs["Incoming"], 2)
    view_side = g.math("LESS_THAN", vz, 0.0, column=3)
    scaled = frame_scaled(g, frame, vx, vy, vz, 3)
    vu, vv = hemi_octahedral(g, *scaled, 3)
    return vz, view_side, vu, vv, scaled
