"""Step 6 for a colour-free material: the yarn colours at the picked texel
(the group's colour inputs, or per thread the colour strips) and the five
parts' sums turned into radiance with them."""
from .common import mix


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


def thread_places(g, crossings, strips, info, col):
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


def strip_places(g, texel, strips, col):
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
        out.append(mix(g, "MIX", gin[f"{family} colour"], tex.outputs["Color"],
                        gin[f"{family} per thread"], col + 2))
    return out


def coloured(g, gin, sums, places, sides, strips, levels, col):
    """Colour-free sums [S, W, F, Wn, Fn] per accumulator into radiance:
    S + W c_warp + F c_weft + Wn c_warp_next + Fn c_weft_next
    (docs/formats/material.md), channel by channel, so a coloured light's
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
            rgb = mix(g, "ADD", rgb, mix(g, "MULTIPLY", part, colour, 1.0, col + 3), 1.0,
                       col + 4)
        out.append(rgb)
    return out
