"""View directions of a lookup: the hemi-octahedral and polar K x K grids of
docs/lookup-format.md, mirrored from baker/core/bake/direction_grid.cpp.

Directions are in the local frame (T, B, N) of a surface point and point
from the surface toward the eye. z >= 0 is the front side (side 0), z < 0 the
back (side 1, the same map with z mirrored).
"""
import math
from dataclasses import dataclass

HEMI_OCTAHEDRAL = "hemi-octahedral"
POLAR = "polar"


def hemi_oct_encode(d):
    """(u, v) in [0, 1]^2 of a direction (a negative z is taken as its mirror)."""
    x, y, z = d
    norm = abs(x) + abs(y) + abs(z)
    if not norm > 0.0:
        return 0.5, 0.5
    px, py = x / norm, y / norm
    return (min(max((px + py + 1.0) * 0.5, 0.0), 1.0),
            min(max((px - py + 1.0) * 0.5, 0.0), 1.0))


def hemi_oct_decode(u, v):
    """Unit direction (z >= 0) of (u, v) in [0, 1]^2."""
    a, b = 2.0 * u - 1.0, 2.0 * v - 1.0
    px, py = 0.5 * (a + b), 0.5 * (a - b)
    z = max(0.0, 1.0 - abs(px) - abs(py))
    n = math.sqrt(px * px + py * py + z * z)
    return px / n, py / n, z / n


@dataclass
class Footprint:
    """The four nodes (i0|i1, j0|j1) of one side a direction blends, and the
    weights fx of i1 and fy of j1."""
    side: int
    i0: int
    i1: int
    j0: int
    j1: int
    fx: float
    fy: float


def node_index(k, side, i, j):
    """Index of node (side, i, j) as in the manifest's `baked` strings."""
    return (side * k + j) * k + i


def node_direction(k, side, i, j, kind=HEMI_OCTAHEDRAL):
    if kind == POLAR:
        phi = 2.0 * math.pi * i / k
        theta = 0.5 * math.pi * j / (k - 1)
        d = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))
    else:
        d = hemi_oct_decode(i / (k - 1), j / (k - 1))
    return (d[0], d[1], -d[2]) if side == 1 else d


def locate(k, d, kind=HEMI_OCTAHEDRAL):
    """The Footprint of direction d (local frame, toward the eye)."""
    side = 0 if d[2] >= 0.0 else 1
    if kind == POLAR:
        length = math.sqrt(sum(c * c for c in d))
        z = abs(d[2]) / length if length > 0 else 1.0
        theta = math.acos(min(max(z, 0.0), 1.0))
        phi = math.atan2(d[1], d[0])
        if phi < 0.0:
            phi += 2.0 * math.pi
        gx = phi / (2.0 * math.pi) * k
        gy = min(max(theta / (0.5 * math.pi) * (k - 1), 0.0), k - 1.0)
        i0 = min(int(gx), k - 1)
        j0 = min(int(gy), k - 2)
        return Footprint(side, i0, 0 if i0 + 1 == k else i0 + 1, j0, j0 + 1,
                         min(max(gx - i0, 0.0), 1.0), min(max(gy - j0, 0.0), 1.0))
    u, v = hemi_oct_encode(d)
    gx, gy = u * (k - 1), v * (k - 1)
    i0 = min(int(gx), k - 2)
    j0 = min(int(gy), k - 2)
    return Footprint(side, i0, i0 + 1, j0, j0 + 1,
                     min(max(gx - i0, 0.0), 1.0), min(max(gy - j0, 0.0), 1.0))
