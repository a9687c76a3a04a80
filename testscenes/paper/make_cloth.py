#!/usr/bin/python3
"""Writes cloth.obj: the paper's 64-quad cloth (Kimoto & Ohno, Figure 5 setting).

A square cloth, 2 x 2 world units of material, lies on an (invisible) table
and hangs over its rounded front edge (the edge runs along x at y = 0, the
table top is y = 0, z < 0, the cloth hangs in front, z >= 0, down to about
y = -1.3). Folds start as low ridges on the table top and deepen toward the
hem; their depth changes across the width (deep on the left, shallow on the
right), they lean a little as they fall, and the left of the skirt swings out
from the table. The mesh is 8 x 8 quads on a 9 x 9 grid of shared vertices
and UVs: u = i/8 across (x), v = j/8 from the hem (v = 0) to the back edge
(v = 1); faces are counter-clockwise seen from the front (the side away from
the table), so the cloth volume lies on the table side.

The shape is nearly isometric to the flat material, so a weave repeat keeps
its size and shape everywhere: along each row every edge has the material
length 2/8 (the folds pull the rows in, narrowing the hem), and each column
is resampled to the same edge length along its folded length (deep folds
lift the hem). One UV unit is therefore 2 world units in u and in v (within
the few per cent printed when the script runs).

Usage: make_cloth.py [OUT.obj]   (default: cloth.obj next to this script)
"""

import math
import os
import sys

import numpy as np

N = 8  # quads per side (8 x 8 = 64, as in the paper)
SIZE = 2.0  # material width and length, world units
H = SIZE / N  # material length of every quad edge
EDGE_RADIUS = 0.2  # radius of the table's rounded front edge
BEND_MID = 0.75  # material distance from the back edge to the middle of the bend
FOLD_START = 0.1  # folds begin this far from the back edge (on the table top)
FOLD_DEPTH = 0.32  # deepest fold at the hem, world units
SWING = 0.25  # how far the left end of the hem swings forward
FOLDS = 2  # fold periods across the width


def profile(s):
    """Point (y, z) and outward normal (ny, nz) of the flat cloth's cross-section
    at material distance s from the back edge: table top (y = 0), quarter circle
    round the edge, then hanging straight down in the plane z = 0."""
    r = EDGE_RADIUS
    top = BEND_MID - math.pi * r / 4  # flat length on the table before the bend
    if s < top:
        return np.array([0.0, -r - top + s]), np.array([1.0, 0.0])
    if s < top + math.pi * r / 2:
        phi = (s - top) / r
        return (np.array([-r + r * math.cos(phi), -r + r * math.sin(phi)]),
                np.array([math.cos(phi), math.sin(phi)]))
    return np.array([-r - (s - top - math.pi * r / 2), 0.0]), np.array([0.0, 1.0])


def fold_offsets(s):
    """Displacement along the profile normal of the 9 vertices of the row at s."""
    if s <= FOLD_START:
        return np.zeros(N + 1)
    ramp = (s - FOLD_START) / (SIZE - FOLD_START)
    u = np.arange(N + 1) / N
    depth = 0.7 + 0.3 * np.cos(math.pi * (1.2 * u + 0.1))  # deep left, shallow right
    lean = 0.06 * (s - FOLD_START)  # the folds drift sideways as they fall
    folds = FOLD_DEPTH * ramp * depth * (0.5 - 0.5 * np.cos(2 * math.pi * (FOLDS * u + lean)))
    # The left part of the skirt swings out from the table a little.
    swing = SWING * ramp**2 * (1.0 - u) ** 2
    return folds + swing


def row(s):
    """The 9 vertices of the folded row at material distance s; each edge of the
    row keeps the material length H (the folds pull the row in)."""
    (y, z), (ny, nz) = profile(s)
    d = fold_offsets(s)
    step = np.diff(d)
    assert np.all(np.abs(step) < H), "folds too deep for the quad size"
    x = np.concatenate([[0.0], np.cumsum(np.sqrt(H * H - step**2))])
    return np.stack([x - 0.5 * x[-1], y + ny * d, z + nz * d], axis=-1)


def build():
    # Sample the folded surface finely along s, then walk down each column
    # and place a vertex every H of 3-D arc length: the columns keep the
    # material length too (deep folds lift the hem).
    fine_s = np.linspace(0.0, SIZE, 4001)
    fine = np.stack([row(s) for s in fine_s])  # [s, i, xyz]
    p = np.zeros((N + 1, N + 1, 3))  # p[j, i] = (x, y, z); j = 0 is the hem
    for i in range(N + 1):
        steps = np.linalg.norm(np.diff(fine[:, i], axis=0), axis=1)
        arc = np.concatenate([[0.0], np.cumsum(steps)])
        for k in range(N + 1):
            target = min(k * H, arc[-1])
            for c in range(3):
                p[N - k, i, c] = np.interp(target, arc, fine[:, i, c])
    return p


def write_obj(p, path):
    with open(path, "w", newline="\n") as f:
        f.write("# clothbake testscenes/paper/cloth.obj, written by make_cloth.py; do not edit.\n")
        f.write(f"# {N} x {N} quads, {SIZE:g} x {SIZE:g} world units of material, draped over a\n")
        f.write("# table edge with folds. u across (x), v from the hem (0) to the back edge (1).\n")
        f.write("o cloth\n")
        for j in range(N + 1):
            for i in range(N + 1):
                x, y, z = p[j, i]
                f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        for j in range(N + 1):
            for i in range(N + 1):
                f.write(f"vt {i / N:.6f} {j / N:.6f}\n")
        for j in range(N):
            for i in range(N):
                a = j * (N + 1) + i + 1  # 1-based; corners counter-clockwise from the front
                c = [a, a + 1, a + N + 2, a + N + 1]
                f.write("f " + " ".join(f"{k}/{k}" for k in c) + "\n")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "cloth.obj")
    p = build()
    write_obj(p, out)
    # Report how close to isometric the shape is (edge lengths vs H).
    du = np.linalg.norm(np.diff(p, axis=1), axis=2)
    dv = np.linalg.norm(np.diff(p, axis=0), axis=2)
    lo, hi = p.reshape(-1, 3).min(axis=0), p.reshape(-1, 3).max(axis=0)
    print(f"wrote {out}: bbox {np.round(lo, 3)} .. {np.round(hi, 3)}; "
          f"edge length / {H:g}: u {du.min() / H:.3f}..{du.max() / H:.3f}, "
          f"v {dv.min() / H:.3f}..{dv.max() / H:.3f}")


if __name__ == "__main__":
    main()
