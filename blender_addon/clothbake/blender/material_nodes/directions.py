"""Direction maths in nodes, node for node core/directions.py's: a
direction into the shading frame, its hemi-octahedral square, the light
map's horizon warp and the stochastic pick of a direction node."""


def to_frame(g, frame, d, column):
    """d in the frame: (d.T, d.B, d.N)."""
    return (g.vmath("DOT_PRODUCT", d, frame.tangent, column=column),
            g.vmath("DOT_PRODUCT", d, frame.bitangent, column=column),
            g.vmath("DOT_PRODUCT", d, frame.normal, column=column))


def hemi_octahedral(g, x, y, z, column):
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


def horizon_warp(g, u, v, column):
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


def pick_node(g, coord, nodes, xi, column):
    """Node floor(coord (nodes - 1) + xi), at most nodes - 1: node i0 + 1
    with probability frac, the bilinear weight."""
    return g.math("MINIMUM", g.math("FLOOR", g.math("MULTIPLY_ADD", coord, float(nodes - 1),
                                                    xi, column=column), column=column),
                  float(nodes - 1), column=column)
