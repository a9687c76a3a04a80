"""Step 2 (with step 4's tile): where in the repeat the shading point is,
the texel picked there, and the pack's address of its tile; per repeat or,
for a material addressed per crossing, per crossing."""
from .common import Texel


def _repeat_coords(g, gin, shift):
    """The UV map in repeats (x, y), shifted by the view node's parallax
    (parallax_shift, in repeats) when `shift` is not None."""
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


def texel_address(g, gin, pack, k, view, level, xi_x, xi_y, shift=None):
    """Steps 2 and 4: the texel (periodic, stochastic bilinear) and the
    address of component 0's tile; returns (uv0, the step to component k,
    Texel: where the pick landed, for the colour strips). `shift`: the view
    node's parallax shift in repeats (parallax_shift), or None."""
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


def crossing_address(g, gin, info, pack, view, level, xi_x, xi_y, index_image, shift=None,
                      span_image=None):
    """Steps 2 and 4 for a material addressed per crossing
    (docs/formats/material.md, "Addressed per crossing"): every crossing
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
