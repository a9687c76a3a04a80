"""Where a quad's texels are, and its local frame: what the Blender layer
writes onto a mesh and into small images so plain shader nodes can address
a packed lookup (docs/formats/lookup.md, version 2).

* Per face (FACE-domain attributes, world space): the quad's bilinear patch
  (p0, e, f, g), its UV Jacobian terms (ue, uf, ug) from the weave's UV
  map, and (quad index, square size). The shader inverts the patch along
  the view ray to get the patch parameters (s, t) clothbake's renderer uses,
  and builds the frame (T, B, N) there (patch_parameters,
  frame_from_attributes below are its arithmetic, step for step).
* Per side, an **index image** of K^2 x quads float pixels: pixel (node, q)
  holds where that (quad, node) square starts in the side's atlas, in UV
  units, and whether it is baked (index_pixels). The shader reads it with
  Closest filtering, then the atlas at
  ``(x0 + s size / W, y0 + t size / H)`` with Linear filtering.
"""
import math
import struct

# Patch parameters (s, t) of corners 0..3 (docs/formats/lookup.md).
CORNER_ST = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _add_scaled(a, b, k):
    return (a[0] + b[0] * k, a[1] + b[1] * k, a[2] + b[2] * k)


def _scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _normalized(a):
    n = math.sqrt(_dot(a, a))
    return _scale(a, 1.0 / n) if n > 0.0 else (0.0, 0.0, 0.0)


def _bilerp_derivatives(c, s, t):
    """d/ds and d/dt of the bilinear patch through c[0..3] (any dimension)."""
    n = len(c[0])
    ds = tuple((c[1][i] - c[0][i]) * (1 - t) + (c[2][i] - c[3][i]) * t for i in range(n))
    dt = tuple((c[3][i] - c[0][i]) * (1 - s) + (c[2][i] - c[1][i]) * s for i in range(n))
    return ds, dt


def patch_frame(corners_world, corners_uv, s, t):
    """(T, N) of the patch at (s, t): unit vectors, world space.

    Mirrors QuadPatch::frame: the world tangent per unit of u is the first
    column of J M^-1 (J the patch's world Jacobian, M its UV Jacobian); T is
    it projected into the tangent plane. Scale factors (repeats, mm) cancel
    in the direction. Returns None for a degenerate patch.
    """
    ps, pt = _bilerp_derivatives(corners_world, s, t)
    us, ut = _bilerp_derivatives(corners_uv, s, t)
    det = us[0] * ut[1] - ut[0] * us[1]
    n = _cross(ps, pt)
    if det == 0.0 or _dot(n, n) == 0.0:
        return None
    n = _normalized(n)
    dp_du = _scale(_add_scaled(_scale(ps, ut[1]), pt, -us[1]), 1.0 / det)
    tangent = _normalized(_add_scaled(dp_du, n, -_dot(dp_du, n)))
    if _dot(tangent, tangent) == 0.0:
        return None
    return tangent, n


def corner_frames(corners_world, corners_uv):
    """(T, N) at each of the four corners; None if the patch is degenerate."""
    frames = [patch_frame(corners_world, corners_uv, s, t) for s, t in CORNER_ST]
    return None if any(f is None for f in frames) else frames


# --- Exact patch parameters in the shader ---------------------------------
#
# Blender renders a quad as two triangles, and interpolates anything stored
# per corner linearly over each. clothbake's reference renderer intersects
# the bilinear patch itself. On a quad that is not a parallelogram the two
# parameterisations differ by up to a quarter of the twist vector
# p0 - p1 + p2 - p3, which on the paper's draped cloth shifts the weave by a
# sizeable part of a period and shows as moire in a comparison. So the
# shader recomputes the patch parameters per shading point: the view ray
# through the triangle's hit point P, direction I, meets the patch where
#     h = s e + t f + s t g        (projected along I)
# with h = P - p0, e = p1 - p0, f = p3 - p0, g = p0 - p1 + p2 - p3. Crossing
# with (e + t g) and taking the component along I, C(a, b) = (a x b) . I,
# leaves  k2 t^2 + k1 t + k0 = 0,  k2 = C(g, f), k1 = C(e, f) + C(h, g),
# k0 = C(h, e),  solved in the cancellation-free form, and s by least
# squares from  h - t f = s (e + t g)  projected along I.
# face_attributes() is what the mesh stores per face; patch_parameters()
# is the node tree's arithmetic, step for step, so tests can check it here.

def face_attributes(corners_world, corners_uv, face):
    """Per-face vectors the shader reads, as the patch modifier
    (blender/lookup_patch_nodes.py) stores them: the patch (p0, e, f, g), its UV
    Jacobian terms (ue, uf, ug, as (u, v, 0)) and (face index, 0, 0)."""
    p = corners_world
    uv = corners_uv
    e = _sub(p[1], p[0])
    f = _sub(p[3], p[0])
    g = tuple(p[0][i] - p[1][i] + p[2][i] - p[3][i] for i in range(3))
    ue = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1], 0.0)
    uf = (uv[3][0] - uv[0][0], uv[3][1] - uv[0][1], 0.0)
    ug = (uv[0][0] - uv[1][0] + uv[2][0] - uv[3][0], uv[0][1] - uv[1][1] + uv[2][1] - uv[3][1], 0.0)
    return {"p0": tuple(p[0]), "e": e, "f": f, "g": g, "ue": ue, "uf": uf, "ug": ug,
            "face": (float(face), 0.0, 0.0)}


def index_pixels(lookup_object, side, k, hidden=()):
    """RGBA float pixels (rows bottom-up, as Blender stores images) of the
    side's index image: K^2 columns (the side's nodes, j K + i), one row per
    quad. Pixel (n, q) = (x0, y0, size, 1): the square of (q, n) starts at
    UV (x0, y0) of the atlas (its bottom-left corner: the atlas's rows run
    top-down, UVs bottom-up) and is `size` texels wide, 0 when the pair is
    not baked (or quad q is in `hidden`). The shader multiplies texels of
    size-0 pairs by 0, so they are transparent, as in clothbake's
    lookup-render (which skips the whole lookup; the two differ only where
    some of the four nodes are baked and some not, which a bake never
    plans)."""
    name = ("front", "back")[side]
    atlas = lookup_object.sides[name]
    per_side = k * k
    pixels = [0.0] * (per_side * lookup_object.quads * 4)
    for q in range(lookup_object.quads):
        size = lookup_object.sizes[q]
        for local in range(per_side):
            at = (q * per_side + local) * 4
            pixels[at + 3] = 1.0
            node = side * per_side + local
            if atlas is None or q in hidden or not lookup_object.is_baked(q, node):
                continue
            x, y = atlas.squares[q, node]
            pixels[at] = x / atlas.width
            pixels[at + 1] = 1.0 - (y + size) / atlas.height
            pixels[at + 2] = float(size)
    return pixels


def atlas_uv(lookup_object, side, quad, node, s, t):
    """UV (bottom-left origin) of patch point (s, t) in the square of
    (quad, node): the index image's (x0, y0) plus (s, t) times the square's
    size over the atlas's; what the shader computes."""
    atlas = lookup_object.sides[("front", "back")[side]]
    x, y = atlas.squares[quad, node]
    size = lookup_object.sizes[quad]
    return (x / atlas.width + s * size / atlas.width,
            1.0 - (y + size) / atlas.height + t * size / atlas.height)


def f32(x):
    """x rounded to float32, as the shader's Math nodes compute."""
    return struct.unpack("f", struct.pack("f", x))[0]


def _clamp(x, lo, hi):
    return min(max(x, lo), hi)


def _safe_div(a, b):
    # Cycles' Math node DIVIDE returns 0 for a zero divisor.
    return a / b if b != 0.0 else 0.0


def patch_parameters(attrs, point, incoming, rnd=float):
    """(s, t) in [0, 1]^2 where the ray through `point` along unit
    `incoming` meets the patch: the shader's arithmetic."""
    e, f, g = attrs["e"], attrs["f"], attrs["g"]
    h = _sub(point, attrs["p0"])

    def c(a, b):
        return _dot(_cross(a, b), incoming)

    k2 = c(g, f)
    k1 = c(e, f) + c(h, g)
    k0 = c(h, e)
    root = math.sqrt(max(k1 * k1 - 4.0 * k0 * k2, 0.0))
    q = -0.5 * (k1 + (root if k1 > 0.0 else -root))
    # Both roots clamped to [-1, 2] first: the shader selects between them
    # by blending with a 0/1 weight, which loses t_near to cancellation when
    # t_far is huge (k2 ~ 0, a parallelogram up to rounding); clamped, the
    # blend is exact to float precision. `rnd` rounds each step of the
    # blend: f32 to emulate the shader's float32 Math nodes.
    t_near = _clamp(_safe_div(k0, q), -1.0, 2.0)  # the root that stays finite as k2 -> 0
    t_far = _clamp(_safe_div(q, k2), -1.0, 2.0)
    near_ok = 1.0 if abs(t_near - 0.5) < 0.5 + 1e-3 else 0.0
    t = rnd(rnd(near_ok * rnd(t_near - t_far)) + t_far)
    t = min(max(t, 0.0), 1.0)

    def perp(a):
        return _add_scaled(a, incoming, -_dot(a, incoming))

    d1 = perp(_add_scaled(h, f, -t))
    d2 = perp(_add_scaled(e, g, t))
    s = min(max(_safe_div(_dot(d1, d2), _dot(d2, d2)), 0.0), 1.0)
    return s, t


def frame_from_attributes(attrs, s, t):
    """(T, N) at (s, t) from the face attributes: the shader's arithmetic,
    equal to patch_frame()."""
    e, f, g = attrs["e"], attrs["f"], attrs["g"]
    ps = _add_scaled(e, g, t)
    pt = _add_scaled(f, g, s)
    n = _normalized(_cross(ps, pt))
    us = _add_scaled(attrs["ue"], attrs["ug"], t)
    ut = _add_scaled(attrs["uf"], attrs["ug"], s)
    det = us[0] * ut[1] - ut[0] * us[1]
    # dP/du = (ps ut.v - pt us.v) / det; only its direction is needed, so
    # scale by det (same sign) instead of dividing.
    v = _scale(_add_scaled(_scale(ps, ut[1]), pt, -us[1]), det)
    tangent = _normalized(_add_scaled(v, n, -_dot(v, n)))
    return tangent, n
