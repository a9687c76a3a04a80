"""A cloth material (docs/formats/material.md) re-packed for Blender's nodes.

clothbake's material stores, per mip level, an atlas with one channel set
per SVD component (alpha + 3 x max_rank channels) and a light-factor image
indexed by (light node, view node). Blender's Image Texture node reads RGBA,
and a node tree cannot loop, so the Apply step reads two RGBA images whose
addresses a few Math nodes compute (clothbake.blender.material_apply):

coefficients (`coefficients.exr`, half RGBA):
    level L (S = max(1, texels >> L) texels a side, tile pitch P = S + 2)
    occupies rows [Y_L, Y_L + 2 K P) of a band, with
    Y_L = 2 K (2 S0 (1 - 2^-L) + 2 L) (S0 = texels; exact, as every level
    halves S until S = 1). Component k lies in band b = k // per_row (band
    height Y_levels), column block c = k % per_row. View node (side, i, j),
    component k: the tile whose bottom-left pixel is
    ((c K + i) P, b Y_levels + Y_L + (side K + j) P). Texel
    (tx, ty) is pixel (1 + tx, 1 + ty) of the tile; the one-pixel gutter
    holds the periodic neighbours (the weave repeats), so a lookup at
    tile + 1 + floor(t - 0.5 + xi) for xi in [0, 1) is, on average over xi,
    the periodic bilinear blend clothbake's lookup makes.
    RGB = C_L(x, v, k); A = alpha A_L(x, v) (in every component's tile).
    A colour-free material (parts "specular-warp-weft") packs its own
    parts (S, W, F) where an RGB one packs (R, G, B), and its next parts
    into `coefficients_next.exr` at the same addresses: (Wn, Fn, plus_x,
    plus_y), plus_x / plus_y (0 / 1, the same over a view node's tile)
    whether the view node's ray runs toward + x / + y, so that its next
    colours are the owner + 1's (core/yarn_colours.next_sides).

    A material addressed per crossing (docs/formats/material.md, version 3)
    has `blocks` blocks of S x S texels per view node: a tile holds them in
    a grid bx = ceil(sqrt(blocks)) across and by = ceil(blocks / bx) up,
    block b at (b % bx, b // bx), so the tile's pitch is P = bx S + 2
    across and by S + 2 up and Y_L = 2 K (by 2 S0 (1 - 2^-L) + 2 L) (a
    whole repeat is bx = by = 1). Texel (tx, ty) of block b is pixel
    (1 + (b % bx) S + tx, 1 + (b // bx) S + ty) of the tile; every pick
    lands inside its crossing's block, so the gutter stays unused.
    `crossings.exr` (float RGBA, ends x picks) holds, at pixel (end, pick)
    from the bottom, the crossing's block, b % bx and b // bx.

light factors (`light_factors.exr`, float RGBA):
    F(v, n, k) resampled from the material's light nodes (Catmull-Rom, as
    clothbake's lookup blends them) onto a grid of M x M directions per
    side on the material's own light map (plain hemi-octahedral, or drawn
    toward the horizon), so that a bilinear read in nodes stands in for the
    4 x 4 Catmull-Rom clothbake evaluates. Tile of view
    node (side_v, i, j), component group g (components 4g .. 4g+3 in RGBA),
    light side sl: bottom-left pixel (((g K + i) 2 + sl) Q, (side_v K + j) Q),
    Q = M + 2; direction grid node (a, b) is pixel (1 + a, 1 + b) of it.
    Above the tiles, rows [2 K Q, 2 K Q + 2 K): the world factors
    G(v, k, ws) = integral over a hemisphere of F(v, l, k) d omega_l (the
    light factors as clothbake interpolates them, world_weights), ws = 0
    the hemisphere on the view node's own side, 1 the other: view node
    (side_v, i, j), group g at pixel (((g K + i) 2 + ws) Q + 1,
    2 K Q + side_v K + j), the same stride per group as the tiles, so a
    uniform world of radiance W adds W sum_k C_k G_k (the cycles-lit
    route's world term, material_nodes.lights.world_terms).

The first `rank` components of each view node are kept (the SVD orders them
by singular value, so this is each view's best rank-`rank` truncation).

The packed images go into `MATERIAL_DIR/blender-r{rank}-m{M}/` with a
pack.json, written through a temporary folder and a rename, and are reused
while the material's manifest is unchanged.
"""
import hashlib
import math
import json
import os
import shutil
from dataclasses import dataclass

import numpy as np

from .defaults import folder_siblings
from .directions import hemi_oct_decode, hemi_oct_encode, horizon_from_grid, horizon_to_grid
from .errors import ClothbakeError
from .yarn_colours import next_sides
# The material folder's reader; imported here too, as the pack's callers
# (and tests) know it by material_pack.read_material.
from .material_manifest import (CROSSINGS, FORMAT, HORIZON, SQUARE, SWF,  # noqa: F401
                                MaterialInfo, is_material_folder, read_material)

PACK_VERSION = 5
DEFAULT_RANK = 24       # components Blender evaluates (node count grows with it)
DEFAULT_DENSE = 32      # light directions per side of the resampled grid
WORLD_SAMPLES = 1 << 16  # directions per hemisphere of the world factors' quadrature
MAX_WIDTH = 8192        # widest coefficient image: Blender 3.4's Cycles read images
                        # 15232 and 16320 pixels wide as garbage, 13056 right
MAX_SIDE = 16384        # largest texture side Eevee (Mesa llvmpipe) accepts
SPAN_WIDTH = 8192       # samples per repeat of the span image (unevenly spaced threads)


# --- the light grids (baker/core/geometry/direction_grid.cpp, in numpy) --------

def _catmull_rom(t):
    t2, t3 = t * t, t * t * t
    return np.stack([0.5 * (-t3 + 2 * t2 - t), 0.5 * (3 * t3 - 5 * t2 + 2),
                     0.5 * (-3 * t3 + 4 * t2 + t), 0.5 * (t3 - t2)], -1)


def light_node_weights(dirs, kl, light_map, side=None):
    """Weights (n, 2 kl^2) over the material's light nodes for directions
    dirs (n, 3) toward the light, as ClothMaterial::shade blends them
    (Catmull-Rom over the 4 x 4 nodes around, indices clamped). `side`
    (n,) overrides z's sign: a horizon direction of side 1 has z = -0."""
    n = len(dirs)
    side = (dirs[:, 2] < 0).astype(int) if side is None else np.asarray(side, int)
    u, v = hemi_oct_encode(dirs)
    if light_map == HORIZON:
        u, v = horizon_to_grid(u, v)
    gx, gy = u * (kl - 1), v * (kl - 1)
    i0 = np.minimum(gx.astype(int), kl - 2)
    j0 = np.minimum(gy.astype(int), kl - 2)
    wx = _catmull_rom(np.clip(gx - i0, 0, 1))
    wy = _catmull_rom(np.clip(gy - j0, 0, 1))
    out = np.zeros((n, 2 * kl * kl))
    rows = np.arange(n)
    for b in range(4):
        for a in range(4):
            i = np.clip(i0 - 1 + a, 0, kl - 1)
            j = np.clip(j0 - 1 + b, 0, kl - 1)
            np.add.at(out, (rows, (side * kl + j) * kl + i), wx[:, a] * wy[:, b])
    return out


def dense_light_directions(m, light_map=SQUARE):
    """Directions (2 m^2, 3) of the resampled grid, index (sl m + b) m + a,
    and their sides. The grid is laid on the material's own light map, so a
    horizon-drawn material keeps its dense rows at grazing light."""
    g = np.arange(m) / (m - 1)
    u, v = np.meshgrid(g, g)             # v rows (b), u columns (a)
    if light_map == HORIZON:
        u, v = horizon_from_grid(u, v)
    d = hemi_oct_decode(u, v).reshape(-1, 3)
    back = d.copy()
    back[:, 2] = -back[:, 2]
    return np.concatenate([d, back]), np.repeat([0, 1], m * m)


def world_weights(kl, light_map, samples=WORLD_SAMPLES):
    """(2, 2 kl^2): per hemisphere (0: z >= 0), weights over the light
    nodes whose dot product with a view node's factors F(v, ., k) is the
    integral of F over that hemisphere in solid angle, F interpolated
    between the nodes as clothbake's lookup does (light_node_weights). The
    quadrature: `samples` directions of a Fibonacci lattice, equal areas
    (z uniform in (0, 1), the golden angle around), each 2 pi / samples."""
    n = np.arange(samples) + 0.5
    z = n / samples
    phi = n * (math.pi * (3.0 - math.sqrt(5.0)))
    r = np.sqrt(1.0 - z * z)
    front = np.stack([r * np.cos(phi), r * np.sin(phi), z], -1)
    out = np.zeros((2, 2 * kl * kl))
    for side in (0, 1):
        d = front if side == 0 else front * np.array([1.0, 1.0, -1.0])
        for start in range(0, samples, 4096):
            chunk = d[start:start + 4096]
            out[side] += light_node_weights(chunk, kl, light_map,
                                            np.full(len(chunk), side)).sum(0)
    return out * (2.0 * math.pi / samples)


# --- packing ---------------------------------------------------------------

@dataclass
class Pack:
    folder: str           # the pack's folder
    coefficients: str     # path of coefficients.exr
    light_factors: str    # path of light_factors.exr
    rank: int             # components kept (>= 1)
    dense: int            # M
    width: int            # coefficients.exr
    height: int
    per_row: int          # components side by side in one band
    band: int             # rows of one band (all levels)
    light_width: int
    light_height: int
    groups: int           # ceil(rank / 4)
    next_coefficients: str = ""   # colour-free: path of coefficients_next.exr, else ""
    crossings: str = ""   # addressed per crossing: path of crossings.exr, else ""
    spans: str = ""       # addressed on unevenly spaced threads: path of spans.exr, else ""


def level_offset(texels, k, level, by=1):
    """Y_L of the module docstring, in pixels from the bottom: the running
    sum of the levels' tile rows, (by S_l + 2) each."""
    return 2 * k * (by * 2 * texels * (1 - 0.5 ** level) + 2 * level)


def coefficient_layout(info, rank):
    """(width, height, per_row, band): components sit per_row side by side
    in bands of `band` rows (every level), component c in band c // per_row
    at column block c % per_row, so no image is wider than MAX_WIDTH."""
    bx, by = info.block_grid
    block = info.k * (bx * info.texels + 2)
    per_row = max(1, min(rank, MAX_WIDTH // block))
    band = int(round(level_offset(info.texels, info.k, info.levels, by)))
    bands = (rank + per_row - 1) // per_row
    return per_row * block, bands * band, per_row, band



def _read_exr(path, what):
    """All channels as float (H, W, C) and their names. Through ImageInput,
    not ImageBuf: ImageBuf's shared cache would hand back a file's old
    pixels after a re-bake in the same Blender session."""
    import OpenImageIO as oiio  # Debian's python3-openimageio (BLENDER_NOTES.md)
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise ClothbakeError(f"cannot read the {what}: {oiio.geterror()}", path)
    try:
        spec = inp.spec()
        pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
        if pixels is None:
            raise ClothbakeError(f"cannot read the {what}: {inp.geterror()}", path)
        return pixels.reshape(spec.height, spec.width, spec.nchannels), list(spec.channelnames)
    finally:
        inp.close()


def _write_exr(path, rgba, kind):
    """rgba (H, W, 4), row 0 at the bottom as Blender addresses it; EXR rows
    are stored top-down."""
    import OpenImageIO as oiio
    h, w, _ = rgba.shape
    spec = oiio.ImageSpec(w, h, 4, oiio.HALF if kind == "half" else oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "A")
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(path)
    if out is None or not out.open(path, spec):
        raise ClothbakeError(f"cannot write: {oiio.geterror()}", path)
    ok = out.write_image(np.ascontiguousarray(rgba[::-1], dtype=np.float32))
    out.close()
    if not ok:
        raise ClothbakeError(f"cannot write: {out.geterror()}", path)


def _channel(names, name, path):
    try:
        return names.index(name)
    except ValueError:
        raise ClothbakeError(f"has no channel {name}", path) from None


def pack_key(info, rank, dense):
    text = json.dumps(info.manifest, sort_keys=True)
    layout = coefficient_layout(info, rank)
    return hashlib.sha256(f"{PACK_VERSION} {rank} {dense} {layout} {text}".encode()
                          ).hexdigest()[:16]


def blender_rank(info, rank=None):
    """Components Blender evaluates: `rank` (default DEFAULT_RANK), at most
    the material's max_rank and what fits the GPU's widest texture."""
    want = DEFAULT_RANK if rank is None else int(rank)
    if want < 1:
        raise ClothbakeError("must be at least 1", "", "rank")
    bx, by = info.block_grid
    band = level_offset(info.texels, info.k, info.levels, by)
    per_row = max(1, MAX_WIDTH // (info.k * (bx * info.texels + 2)))
    fits = max(1, int(MAX_SIDE // band) * per_row)
    return max(1, min(want, max(1, info.max_rank), fits))


def _layout(info, rank, dense):
    """The Pack of `info` at this rank and grid: where everything goes."""
    folder = os.path.join(info.folder, f"blender-r{rank}-m{dense}")
    groups = (rank + 3) // 4
    width, height, per_row, band = coefficient_layout(info, rank)
    q = dense + 2
    return Pack(folder, os.path.join(folder, "coefficients.exr"),
                os.path.join(folder, "light_factors.exr"), rank, dense, width, height,
                per_row, band, groups * info.k * 2 * q, 2 * info.k * q + 2 * info.k, groups,
                os.path.join(folder, "coefficients_next.exr") if info.parts == SWF else "",
                os.path.join(folder, "crossings.exr") if info.address == CROSSINGS else "",
                os.path.join(folder, "spans.exr") if info.address == CROSSINGS and
                not all(info.even) else "")


def _is_cached(pack, key):
    try:
        with open(os.path.join(pack.folder, "pack.json")) as f:
            return json.load(f).get("key") == key and os.path.isfile(pack.coefficients) and \
                os.path.isfile(pack.light_factors) and \
                (not pack.next_coefficients or os.path.isfile(pack.next_coefficients)) and \
                (not pack.crossings or os.path.isfile(pack.crossings)) and \
                (not pack.spans or os.path.isfile(pack.spans))
    except (OSError, ValueError):
        return False


def _place_level(coeff, info, pack, level, coeff_next=None):
    """Level `level`'s tiles of every kept component into `coeff` (and a
    colour-free material's next parts into `coeff_next`)."""
    k, s0, nb = info.k, info.texels, info.blocks
    bx, by = info.block_grid
    path = os.path.join(info.folder, info.manifest["files"]["levels"][level])
    px, names = _read_exr(path, f"level {level}")
    s = max(1, s0 >> level)
    if px.shape[:2] != (2 * k * nb * s, k * s):
        raise ClothbakeError(f"is {px.shape[1]} x {px.shape[0]} pixels; the manifest says "
                             f"{k * s} x {2 * k * nb * s}", path)
    px_, py_ = bx * s + 2, by * s + 2       # the tile's pitch across and up
    y0 = int(round(level_offset(s0, k, level, by)))
    alpha = px[..., _channel(names, "A", path)]
    # (2K rows of tiles, blocks, S, K columns, S) -> [row, col, block, ty,
    # tx], rows top-down in the file; block b of a view node's tile is its
    # rows b S .. b S + S - 1 (docs/formats/material.md).
    a_t = alpha.reshape(2 * k, nb, s, k, s).transpose(0, 3, 1, 2, 4)
    # (2K, K, blocks, S, S, 2): each view node's next sides over its whole tile
    sides = np.broadcast_to(next_sides(k)[:, :, None, None, None, :], (2 * k, k, nb, s, s, 2))
    for comp in range(pack.rank):
        channels = info.channels
        if comp < info.max_rank:
            parts = np.stack([px[..., _channel(names, f"k{comp:04d}.{c}", path)]
                              for c in channels], -1)
        else:
            parts = np.zeros(px.shape[:2] + (len(channels),), np.float32)
        c_t = parts.reshape(2 * k, nb, s, k, s, len(channels)).transpose(0, 3, 1, 2, 4, 5)
        tile = np.concatenate([c_t[..., :3], a_t[..., None]], -1)   # (2K, K, blocks, S, S, 4)
        if coeff_next is not None:
            tile = np.concatenate([tile, c_t[..., 3:5], sides], -1)     # + (Wn, Fn, px, py)
        tiles = np.zeros((2 * k, k, py_, px_, tile.shape[-1]), np.float32)
        if nb == 1:
            # texel (tx, ty) with ty counted from the repeat's y = 0 (the
            # file's row order inside a tile), placed with the gutter, which
            # holds the periodic neighbours
            tiles[:] = np.pad(tile[:, :, 0], ((0, 0), (0, 0), (1, 1), (1, 1), (0, 0)),
                              mode="wrap")
        else:
            # block b at (b % bx, b // bx) of the tile's grid of S x S
            # blocks; a pick lands inside its crossing's block, so the
            # gutter stays unused
            for b in range(nb):
                x, y = 1 + (b % bx) * s, 1 + (b // bx) * s
                tiles[:, :, y:y + s, x:x + s] = tile[:, :, b]
        for row in range(2 * k):
            for col in range(k):
                x = ((comp % pack.per_row) * k + col) * px_
                y = (comp // pack.per_row) * pack.band + y0 + row * py_
                coeff[y:y + py_, x:x + px_] = tiles[row, col, ..., :4]
                if coeff_next is not None:
                    coeff_next[y:y + py_, x:x + px_] = tiles[row, col, ..., 4:]
    # The tile's row ty is texel y = ty (y up in Blender's image space), so
    # the array is stored bottom-up as it is: nothing to flip per tile.


def _light_factor_image(info, pack):
    """light_factors.exr's pixels: the material's factors resampled onto the
    dense grid, tiled as the module docstring says."""
    k, dense, groups = info.k, pack.dense, pack.groups
    q = dense + 2
    path = os.path.join(info.folder, info.manifest["files"]["light_factors"])
    lf, names = _read_exr(path, "light factors")
    views, nl = 2 * k * k, 2 * info.kl * info.kl
    if lf.shape[:2] != (views, nl):
        raise ClothbakeError(f"is {lf.shape[1]} x {lf.shape[0]} pixels; the manifest says "
                             f"{nl} x {views}", path)
    f = np.zeros((views, nl, groups * 4), np.float32)
    for comp in range(min(pack.rank, info.max_rank)):
        f[..., comp] = lf[..., _channel(names, f"k{comp:04d}", path)]
    dirs, sides = dense_light_directions(dense, info.light_map)
    weights = light_node_weights(dirs, info.kl, info.light_map, sides)
    dense_f = np.einsum("dn,vnc->vdc", weights, f.astype(np.float64)).astype(np.float32)
    dense_f = dense_f.reshape(2, k, k, 2, dense, dense, groups, 4)  # sv, j, i, sl, b, a, g, c
    lights = np.zeros((pack.light_height, pack.light_width, 4), np.float32)
    # The world factors: per view node, the hemisphere on its own side and
    # the other (module docstring).
    hemis = world_weights(info.kl, info.light_map)
    world = np.einsum("sn,vnc->vsc", hemis, f.astype(np.float64))       # (views, 2, groups*4)
    world = world.reshape(2, k, k, 2, groups, 4)                          # sv, j, i, sl, g, c
    for g in range(groups):
        for sv in range(2):
            for j in range(k):
                for i in range(k):
                    for ws in range(2):
                        x = ((g * k + i) * 2 + ws) * q + 1
                        lights[2 * k * q + sv * k + j, x] = world[sv, j, i, sv ^ ws, g]
    for g in range(groups):
        block = np.pad(dense_f[..., g, :], ((0, 0),) * 4 + ((1, 1), (1, 1), (0, 0)), mode="edge")
        for sv in range(2):
            for j in range(k):
                for i in range(k):
                    for sl in range(2):
                        x = ((g * k + i) * 2 + sl) * q
                        y = (sv * k + j) * q
                        lights[y:y + q, x:x + q] = block[sv, j, i, sl]
    return lights


def _crossings_image(info):
    """The per-crossing index re-packed: pixel (e, p), row p counted from
    the bottom as Blender addresses it, holds (block, its column b % bx and
    row b // bx in a tile's grid of blocks, 1), so the nodes read where
    the block lies instead of computing it."""
    path = info.crossings_file
    px, names = _read_exr(path, "crossing index")
    if px.shape[:2] != (info.picks, info.ends):
        raise ClothbakeError(f"is {px.shape[1]} x {px.shape[0]} pixels; the manifest says "
                             f"{info.ends} x {info.picks} (crossings.ends x picks)", path)
    block = px[..., _channel(names, "block", path)]
    if not np.all((block == np.round(block)) & (block >= 0) & (block < info.blocks)):
        raise ClothbakeError(f"holds a block index outside 0..{info.blocks - 1}", path)
    bx, _ = info.block_grid
    return np.stack([block, block % bx, block // bx, np.ones_like(block)], -1)


def span_pixels(centres_mm, repeat_mm, width=SPAN_WIDTH):
    """One family's row of the span image: sample n at u = (n + 0.5) / width
    of the repeat holds (e, start, 1 / span, 1) of the thread whose span
    (between the midpoints to its neighbours' centres, as lookup-render's
    locate_in_span) holds u: e counted from the repeat's first thread, e =
    threads for the next repeat's first (whose span may begin before u = 1),
    start in repeats from the repeat's origin, so that e + (u - start) /
    span is the crossing coordinate (material_nodes.address.crossing_address).
    Near a span's end a sample's thread is the one its centre lies in; the
    nodes' coordinate then runs on past e + 1 by the same slope, which is
    the next thread's crossing, exact to the two widths' difference over
    1 / width."""
    c = np.asarray(centres_mm, np.float64) / float(repeat_mm)
    n = len(c)
    ext = np.concatenate([[c[-1] - 1.0], c, [c[0] + 1.0]])     # threads -1 .. n
    lo = 0.5 * (ext[:-2] + ext[1:-1])                            # span of thread j
    hi = 0.5 * (ext[1:-1] + ext[2:])
    # threads 0 .. n (n: the next repeat's first), their spans
    lo = np.concatenate([lo, [lo[0] + 1.0]])
    hi = np.concatenate([hi, [hi[0] + 1.0]])
    u = (np.arange(width) + 0.5) / width
    e = np.clip(np.searchsorted(hi, u, side="right"), 0, n)
    out = np.ones((width, 4), np.float32)
    out[:, 0] = e
    out[:, 1] = lo[e]
    out[:, 2] = 1.0 / (hi[e] - lo[e])
    return out


def _spans_image(info):
    """The span image: row 0 the warp's (along x), row 1 the weft's."""
    return np.stack([span_pixels(info.centres_mm[f], info.repeat_mm[a])
                     for a, f in enumerate(("warp", "weft"))])


def _write_pack(pack, key, coeff, lights, coeff_next=None, crossings=None, spans=None):
    """The pack's folder, written as a temporary sibling and renamed over
    the old one (the program's NAME.tmp-PID / NAME.old-PID names)."""
    folder = pack.folder
    tmp, old = folder_siblings(folder, os.getpid())
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    try:
        _write_exr(os.path.join(tmp, "coefficients.exr"), coeff, "half")
        _write_exr(os.path.join(tmp, "light_factors.exr"), lights, "float")
        if coeff_next is not None:
            _write_exr(os.path.join(tmp, "coefficients_next.exr"), coeff_next, "half")
        if crossings is not None:
            _write_exr(os.path.join(tmp, "crossings.exr"), crossings, "float")
        if spans is not None:
            _write_exr(os.path.join(tmp, "spans.exr"), spans, "float")
        with open(os.path.join(tmp, "pack.json"), "w") as fh:
            json.dump({"key": key, "rank": pack.rank, "dense": pack.dense, "width": pack.width,
                       "height": pack.height, "per_row": pack.per_row, "band": pack.band,
                       "light_width": pack.light_width, "light_height": pack.light_height,
                       "groups": pack.groups}, fh, indent=2)
        if os.path.isdir(folder):
            os.rename(folder, old)
        os.rename(tmp, folder)
        shutil.rmtree(old, ignore_errors=True)
    except OSError as e:
        shutil.rmtree(tmp, ignore_errors=True)
        raise ClothbakeError(f"cannot write the Blender images: {e.strerror}", folder) from None


def pack_material(info, rank=None, dense=DEFAULT_DENSE, progress=None):
    """The Pack of `info` (MaterialInfo), made once and reused."""
    rank = blender_rank(info, rank)
    if not 2 <= dense <= 64:
        raise ClothbakeError("must be in 2..64", "", "dense")
    pack = _layout(info, rank, dense)
    key = pack_key(info, rank, dense)
    if _is_cached(pack, key):
        return pack
    crossings = _crossings_image(info) if pack.crossings else None
    spans = _spans_image(info) if pack.spans else None
    coeff = np.zeros((pack.height, pack.width, 4), np.float32)
    coeff_next = np.zeros_like(coeff) if pack.next_coefficients else None
    for level in range(info.levels):
        if progress:
            progress(level / (info.levels + 1))
        _place_level(coeff, info, pack, level, coeff_next)
    lights = _light_factor_image(info, pack)
    if progress:
        progress(info.levels / (info.levels + 1))
    _write_pack(pack, key, coeff, lights, coeff_next, crossings, spans)
    if progress:
        progress(1.0)
    return pack
