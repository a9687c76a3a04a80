"""Step 4: the random numbers of the stochastic picks, the view node picked
from them, and (a material baked with --view-parallax) where that node is
read."""
from .directions import pick_node

PARALLAX_MIN_Z = 0.0174524  # sin(1 deg): view_parallax.h k_parallax_min_z, the bake's horizon clamp


def randoms(g, position, area=False):
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


def view_node(g, k, view_side, vu, vv, xi_i, xi_j):
    """Step 4: the view node (i, side K + j), picked stochastically; and j."""
    vi = pick_node(g, vu, k, xi_i, 5)
    vj = pick_node(g, vv, k, xi_j, 5)
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


def parallax_shift(g, info, scaled, vi, vj):
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
