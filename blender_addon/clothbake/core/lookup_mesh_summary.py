"""The few numbers a lookup records of the mesh it was baked from
(docs/formats/lookup.md, `objects[o].mesh`; baker/core/geometry/mesh_summary.h), and
the comparison with a mesh in Blender: a lookup baked from another mesh with
the same number of quads, or from this one before it was moved, is refused.

The add-on cannot recompute clothbake's scene hash (exact float bits of the
OBJ it read), so it compares these within tolerances instead: a mesh that
went to an OBJ file (6 decimals) and back must still match."""
import math

from .errors import ClothbakeError

KEYS = ("bounds_min", "bounds_max", "uv_min", "uv_max", "mean_centre", "area")
_LENGTHS = {"bounds_min": 3, "bounds_max": 3, "uv_min": 2, "uv_max": 2, "mean_centre": 3}

# Positions: this fraction of the bounds' diagonal; UVs: absolute; area:
# relative. Far above the OBJ round trip (5e-7 absolute per coordinate) and
# far below a moved vertex of a real cloth.
POSITION_TOLERANCE = 1e-4
UV_TOLERANCE = 1e-4
AREA_TOLERANCE = 1e-3


def summarize(quads):
    """The summary of quads given as (four world corners, four UVs) pairs:
    bounds of the corners and of the UVs, the mean over quads of the mean of
    the four corners, and the sum of |(p2 - p0) x (p3 - p1)| / 2."""
    if not quads:
        return {"bounds_min": [0.0] * 3, "bounds_max": [0.0] * 3, "uv_min": [0.0] * 2,
                "uv_max": [0.0] * 2, "mean_centre": [0.0] * 3, "area": 0.0}
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    uv_lo, uv_hi = [math.inf] * 2, [-math.inf] * 2
    centre = [0.0] * 3
    area = 0.0
    for corners, uvs in quads:
        for p in corners:
            for a in range(3):
                lo[a], hi[a] = min(lo[a], p[a]), max(hi[a], p[a])
                centre[a] += 0.25 * p[a]
        for uv in uvs:
            for a in range(2):
                uv_lo[a], uv_hi[a] = min(uv_lo[a], uv[a]), max(uv_hi[a], uv[a])
        d0 = [corners[2][a] - corners[0][a] for a in range(3)]
        d1 = [corners[3][a] - corners[1][a] for a in range(3)]
        cross = (d0[1] * d1[2] - d0[2] * d1[1], d0[2] * d1[0] - d0[0] * d1[2],
                 d0[0] * d1[1] - d0[1] * d1[0])
        area += 0.5 * math.sqrt(sum(c * c for c in cross))
    n = len(quads)
    return {"bounds_min": lo, "bounds_max": hi, "uv_min": uv_lo, "uv_max": uv_hi,
            "mean_centre": [c / n for c in centre], "area": area}


def parse(value, path, where):
    """A manifest's `mesh` entry checked (None stays None: older lookups)."""
    if value is None:
        return None
    if not isinstance(value, dict):
        raise ClothbakeError("must be an object", path, where)
    out = {}
    for key in KEYS:
        if key not in value:
            raise ClothbakeError("missing", path, f"{where}.{key}")
        v = value[key]
        n = _LENGTHS.get(key)
        ok = (isinstance(v, list) and len(v) == n and all(_finite(x) for x in v)) if n else \
            (_finite(v) and v >= 0)
        if not ok:
            what = f"{n} finite numbers" if n else "a finite number >= 0"
            raise ClothbakeError(f"must be {what}", path, f"{where}.{key}")
        out[key] = [float(x) for x in v] if n else float(v)
    return out


def _finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def difference(baked, here):
    """None when the summary `here` (of a Blender mesh) matches `baked` (the
    lookup's) within the tolerances; else what differs, in words."""
    diag = math.dist(baked["bounds_min"], baked["bounds_max"])
    pos_tol = POSITION_TOLERANCE * max(diag, 1e-6)
    for key, label in (("bounds_min", "lower bounds"), ("bounds_max", "upper bounds"),
                       ("mean_centre", "mean quad centre")):
        if math.dist(baked[key], here[key]) > pos_tol:
            return (f"its {label} are {_fmt(here[key])} in world space, the baked mesh's "
                    f"{_fmt(baked[key])}")
    for key, label in (("uv_min", "lower UV bounds"), ("uv_max", "upper UV bounds")):
        if math.dist(baked[key], here[key]) > UV_TOLERANCE:
            return f"its {label} are {_fmt(here[key])}, the baked mesh's {_fmt(baked[key])}"
    if abs(baked["area"] - here["area"]) > AREA_TOLERANCE * max(baked["area"], 1e-12):
        return f"its area is {here['area']:.6g}, the baked mesh's {baked['area']:.6g}"
    return None


def _fmt(v):
    return "(" + ", ".join(f"{x:.6g}" for x in v) + ")"
