"""View directions of a lookup: the hemi-octahedral and polar K x K grids of
docs/formats/lookup.md, mirrored from baker/core/geometry/direction_grid.cpp.

Directions are in the local frame (T, B, N) of a surface point and point
from the surface toward the eye. z >= 0 is the front side (side 0), z < 0 the
back (side 1, the same map with z mirrored).
"""
import math
from dataclasses import dataclass

import numpy as np

HEMI_OCTAHEDRAL = "hemi-octahedral"
POLAR = "polar"


def hemi_oct_encode(d):
    """(u, v) in [0, 1]^2 of directions d (a 3-tuple or an array (..., 3));
    a negative z is taken as its mirror, the zero vector maps to the centre.
    The one Python copy of the map: the lookup's tests and the material's
    light grids (material_pack) both read it."""
    d = np.asarray(d, dtype=float)
    norm = np.abs(d).sum(-1)
    norm = np.where(norm > 0, norm, 1.0)
    px, py = d[..., 0] / norm, d[..., 1] / norm
    return np.clip((px + py + 1) * 0.5, 0, 1), np.clip((px - py + 1) * 0.5, 0, 1)


def hemi_oct_decode(u, v):
    """Unit directions (z >= 0), shape (..., 3), of (u, v) in [0, 1]^2."""
    a, b = 2 * np.asarray(u, dtype=float) - 1, 2 * np.asarray(v, dtype=float) - 1
    px, py = 0.5 * (a + b), 0.5 * (a - b)
    z = np.maximum(0.0, 1 - np.abs(px) - np.abs(py))
    d = np.stack([px, py, z], -1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _rescale_diamond(u, v, radius):
    """(u, v) with the diamond's radius rho = |px| + |py| mapped to
    radius(min(rho, 1)), the direction in the diamond kept."""
    a, b = 2 * u - 1, 2 * v - 1
    px, py = 0.5 * (a + b), 0.5 * (a - b)
    rho = np.abs(px) + np.abs(py)
    r = np.minimum(rho, 1.0)
    scale = np.where(rho > 0, radius(r) / np.where(rho > 0, rho, 1), 1.0)
    px, py = px * scale, py * scale
    return (px + py + 1) * 0.5, (px - py + 1) * 0.5


def horizon_to_grid(u, v):
    """The horizon warp (DirectionMap::HemiOctahedralHorizon, the material's
    light map) on the plain map's (u, v): rho -> 1 - sqrt(1 - rho)."""
    gu, gv = _rescale_diamond(u, v, lambda r: 1 - np.sqrt(1 - r))
    return np.clip(gu, 0, 1), np.clip(gv, 0, 1)


def horizon_from_grid(u, v):
    """The inverse of horizon_to_grid: a node's (u, v) on the horizon map to
    the plain square's (rho = 1 - (1 - rho')^2)."""
    return _rescale_diamond(u, v, lambda r: 1 - (1 - r) ** 2)


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
