"""The yarn colours a colour-free material renders with
(docs/formats/material.md, "Colour-free parts"), in numpy, as the program's
core/material/yarn_colours.h makes them: per mip level, the warp colour of
every texel column and the weft colour of every texel row, over the colours'
own repeat (q material repeats when a per-thread colour sequence does not
divide the material's threads), and the same for the owner's neighbours
(owner + 1: "plus", owner - 1: "minus"), which the next parts take.

Which thread's colour: thread j (of the q n threads of the q repeats) owns
the span between the midpoints to its neighbours' centres; a level-0
column's colour is the length-weighted average over the column's span of
the owners' colours (own), or of their neighbours' (plus, minus); level
m + 1 is the pairwise average of level m's, so every level is the exact box
average of level 0's colours. Thread j's colour is colours[j mod len].

The image Blender reads a family's strips from (`strip_layout`,
`strip_pixels`): W = min(q texels, MAX_STRIP_WIDTH) columns; R = ceil(q
texels / W) rows per level; block b (0 own, 1 plus, 2 minus) level m's
q max(1, texels >> m) colours fill rows (b levels + m) R + c // W at
column c mod W; RGBA, row 0 at the bottom (Blender's order), the rest black.
"""
import math

import numpy as np

# Widest strip image: Blender 3.4's Cycles reads images much wider than
# 8192 pixels as garbage (core/material_pack.py's MAX_WIDTH).
MAX_STRIP_WIDTH = 8192
SHIFTS = (0, 1, -1)     # the blocks: own, plus (owner + 1), minus (owner - 1)


def strip_repeats(threads, sequence):
    """q = lcm(threads, sequence length) / threads (1 for a plain family)."""
    n, nc = int(threads), max(1, int(sequence))
    return n * nc // math.gcd(n, nc) // n


def colour_strip(centres_mm, repeat_mm, colours, texels, levels, shift=0):
    """The strip of threads with centres `centres_mm` (ascending, in [0,
    repeat_mm): one material repeat) coloured by `colours` in turn (N x 3;
    one colour for a plain family), for `texels` level-0 texels per repeat:
    a list of `levels` arrays, level m (q max(1, texels >> m), 3). `shift`
    1 (-1): each span takes the colour of its owner's thread + 1 (- 1)."""
    centres = np.asarray(centres_mm, np.float64)
    colours = np.asarray(colours, np.float64).reshape(-1, 3)
    n, nc = len(centres), len(colours)
    q = strip_repeats(n, nc)
    columns = q * texels
    span = float(repeat_mm) * q
    # Threads j = -1 .. q n (the ends wrap around: thread -1 is thread q n - 1
    # of the repeat before), and one more each side for their midpoints.
    j = np.arange(-2, q * n + 2)
    centre = centres[j % n] + np.floor_divide(j, n) * float(repeat_mm)
    mids = 0.5 * (centre[:-1] + centre[1:])          # between j and j + 1
    own = colours[((j[1:-1] + shift) % (q * n)) % nc]
    lo = np.clip(mids[:-1], 0.0, span)
    hi = np.clip(mids[1:], 0.0, span)
    keep = hi > lo
    lo, hi, own = lo[keep], hi[keep], own[keep]
    # The colour's running integral at the spans' ends, read at the columns'
    # edges: exact, as the colour is constant on each span.
    ends = np.concatenate([[lo[0]], hi])
    integral = np.concatenate([np.zeros((1, 3)), np.cumsum(own * (hi - lo)[:, None], axis=0)])
    width = span / columns
    edges = np.arange(columns + 1) * width
    at = np.stack([np.interp(edges, ends, integral[:, c]) for c in range(3)], -1)
    out = [(at[1:] - at[:-1]) / width]
    for _ in range(1, levels):
        fine = out[-1]
        out.append(fine.copy() if len(fine) == 1 else 0.5 * (fine[0::2] + fine[1::2]))
    return out


def family_colours(color, colors):
    """The colour sequence a family's strips are made of: its per-thread
    `colors` when it has any, else its one `color`."""
    seq = [list(c) for c in (colors or [])]
    return seq if seq else [list(color)]


def family_strips(centres_mm, repeat_mm, colours, texels, levels):
    """[own, plus, minus] strips (colour_strip's levels each)."""
    return [colour_strip(centres_mm, repeat_mm, colours, texels, levels, s) for s in SHIFTS]


def strip_layout(q, texels, levels):
    """(W, R, height) of a family's strip image: q repeats of `texels`
    columns, three blocks of `levels` levels."""
    width = min(q * texels, MAX_STRIP_WIDTH)
    rows = -(-q * texels // width)
    return width, rows, rows * levels * len(SHIFTS)


def strip_pixels(strips, width, rows):
    """The image's pixels of family_strips' [own, plus, minus]: (height, W,
    4) float32 in strip_layout's order, alpha 1."""
    levels = len(strips[0])
    px = np.zeros((rows * levels * len(strips), width, 4), np.float32)
    px[..., 3] = 1.0
    for b, strip in enumerate(strips):
        for m, row in enumerate(strip):
            c = np.arange(len(row))
            px[(b * levels + m) * rows + c // width, c % width, :3] = row
    return px


def next_sides(k):
    """Per view node (side, i, j) of the K x K hemi-octahedral grid, whether
    its ray (-d_v) runs toward + x and + y: (2K, K, 2) of 0 / 1, [side K +
    j, i]. The program's float32 arithmetic (direction_grid.cpp's
    hemi_oct_decode; the horizon's rescale and the normalisation keep the
    signs): + when -d.x >= 0, so a node with d.x = 0 takes owner + 1."""
    f = np.float32
    g = np.arange(k, dtype=f) / f(k - 1)
    u, v = np.meshgrid(g, g)                         # [j, i]
    a, b = f(2) * u - f(1), f(2) * v - f(1)
    px, py = f(0.5) * (a + b), f(0.5) * (a - b)
    one = np.stack([(px <= 0), (py <= 0)], -1).astype(np.float32)
    return np.concatenate([one, one])                # z does not change x, y
