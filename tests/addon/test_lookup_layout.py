"""The shader's patch arithmetic (clothbake.core.lookup_layout) against the
bilinear patch it inverts and the C++ frame it mirrors."""
import math
import random

import pytest

from clothbake.core import lookup_layout as L


def bilerp(c, s, t):
    return tuple((1 - s) * (1 - t) * c[0][i] + s * (1 - t) * c[1][i] + s * t * c[2][i] +
                 (1 - s) * t * c[3][i] for i in range(len(c[0])))


def random_quad(rng, twist):
    base = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    return [tuple(x + rng.uniform(-twist, twist) for x in p) for p in base]


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


@pytest.mark.parametrize("twist", [0.0, 0.05, 0.2])
def test_patch_parameters_invert_the_patch_along_the_ray(twist):
    """A point anywhere on the view ray through P(s, t) gives back (s, t):
    the shader finds the patch point the reference renderer hits, whatever
    the triangle Blender hit."""
    rng = random.Random(7)
    uv = [(0.1, 0.2), (0.6, 0.2), (0.6, 0.7), (0.1, 0.7)]
    other = 0
    for _ in range(500):
        c = random_quad(rng, twist)
        attrs = L.face_attributes(c, uv, 3)
        s, t = rng.random(), rng.random()
        incoming = unit((rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.3, 1)))
        offset = rng.uniform(-0.1, 0.1)
        p = tuple(a + offset * b for a, b in zip(bilerp(c, s, t), incoming))
        s2, t2 = L.patch_parameters(attrs, p, incoming)
        if max(abs(s2 - s), abs(t2 - t)) > 1e-9:
            # A ray may cross a strongly twisted patch twice; then the other
            # crossing is an answer too, but it must lie on the ray.
            other += 1
            q = bilerp(c, s2, t2)
            d = [a - b for a, b in zip(q, p)]
            along = sum(a * b for a, b in zip(d, incoming))
            assert math.dist(d, [along * i for i in incoming]) < 1e-9
    # Twice-crossing rays are rare even at twist 0.2 (1 in 500 here).
    assert other <= (0 if twist < 0.1 else 5)


def test_patch_parameters_on_parallelograms_survive_float_rounding():
    """A plane made in Blender is all parallelograms: g is 0 up to rounding,
    so k2 is tiny and the far root huge. The shader picks a root by blending
    with a 0/1 weight in float32; unclamped, that blend lost the near root
    to cancellation and whole quads read t = 0 or 1 (a patchwork of
    stripes). The mirror emulates the float32 blend."""
    rng = random.Random(11)
    uv = [(0.0, 0.0), (0.125, 0.0), (0.125, 0.125), (0.0, 0.125)]
    worst = 0.0
    for _ in range(500):
        origin = tuple(rng.uniform(-2, 2) for _ in range(3))
        e = tuple(rng.uniform(-0.3, 0.3) for _ in range(3))
        f = tuple(rng.uniform(-0.3, 0.3) for _ in range(3))
        # rounding-sized twist, as a rotated plane's world corners carry
        tw = tuple(rng.uniform(-1e-7, 1e-7) for _ in range(3))
        c = [origin, tuple(o + a for o, a in zip(origin, e)),
             tuple(o + a + b + w for o, a, b, w in zip(origin, e, f, tw)),
             tuple(o + b for o, b in zip(origin, f))]
        n = unit(tuple(L._cross(e, f)))
        if abs(L._dot(n, n)) < 0.5:
            continue
        s, t = rng.random(), rng.random()
        side = unit(tuple(rng.uniform(-1, 1) for _ in range(3)))
        incoming = unit(tuple(a + 0.7 * b for a, b in zip(n, side)))
        if abs(L._dot(incoming, n)) < 0.2:
            continue
        p = bilerp(c, s, t)
        s2, t2 = L.patch_parameters(L.face_attributes(c, uv, 0), p, incoming, rnd=L.f32)
        worst = max(worst, abs(s2 - s), abs(t2 - t))
    assert worst < 1e-4


def test_triangles_differ_from_the_patch_on_a_twisted_quad():
    """Why the shader inverts the patch: the corner-interpolated (s, t) of
    Blender's triangle (0, 1, 2) misses the patch's by a visible amount."""
    c = [(0, 0, 0), (1, 0, 0.0), (1.5, 1, 0.3), (0, 1, 0)]
    s, t = 0.7, 0.3  # in triangle (0, 1, 2)
    p = bilerp(c, s, t)
    # barycentric (s, t) of p's projection on triangle 0-1-2, viewed along z
    (x0, y0, _), (x1, y1, _), (x2, y2, _) = c[0], c[1], c[2]
    det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    b1 = ((p[0] - x0) * (y2 - y0) - (x2 - x0) * (p[1] - y0)) / det
    b2 = ((x1 - x0) * (p[1] - y0) - (p[0] - x0) * (y1 - y0)) / det
    s_tri, t_tri = b1 + b2, b2  # corners' (s, t): 0 (0,0), 1 (1,0), 2 (1,1)
    assert abs(s_tri - s) + abs(t_tri - t) > 0.02
    attrs = L.face_attributes(c, [(0, 0), (1, 0), (1, 1), (0, 1)], 0)
    s2, t2 = L.patch_parameters(attrs, p, (0.0, 0.0, 1.0))
    assert (s2, t2) == pytest.approx((s, t), abs=1e-9)


def test_frame_matches_patch_frame_and_is_orthonormal():
    rng = random.Random(3)
    for mirrored in (False, True):
        uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
        if mirrored:
            uv = [(1 - u, v) for u, v in uv]
        for _ in range(200):
            c = random_quad(rng, 0.2)
            s, t = rng.random(), rng.random()
            attrs = L.face_attributes(c, uv, 0)
            tan, n = L.frame_from_attributes(attrs, s, t)
            tan2, n2 = L.patch_frame(c, uv, s, t)
            assert tan == pytest.approx(tan2, abs=1e-12)
            assert n == pytest.approx(n2, abs=1e-12)
            assert sum(a * b for a, b in zip(tan, n)) == pytest.approx(0.0, abs=1e-12)


def test_tangent_follows_u_and_flips_with_mirrored_uvs():
    c = [(0, 0, 0), (2, 0, 0), (2, 1, 0), (0, 1, 0)]
    tan, n = L.patch_frame(c, [(0, 0), (1, 0), (1, 1), (0, 1)], 0.5, 0.5)
    assert tan == pytest.approx((1, 0, 0)) and n == pytest.approx((0, 0, 1))
    tan, n = L.patch_frame(c, [(1, 0), (0, 0), (0, 1), (1, 1)], 0.5, 0.5)
    assert tan == pytest.approx((-1, 0, 0)) and n == pytest.approx((0, 0, 1))


def test_atlas_uv_addresses_texel_centres_as_the_format_says():
    """Texel (a, b) of a square is centred at s = (a + .5)/size,
    t = 1 - (b + .5)/size, and is atlas pixel (x + a, y + b), rows from the
    top (docs/formats/lookup.md); as a UV with a bottom-left origin that is
    ((x + a + .5)/W, 1 - (y + b + .5)/H). The index image holds the square's
    origin the shader adds (s, t) x size to, and the size (0: not baked)."""
    from clothbake.core.lookup_manifest import LookupObject, SideAtlas
    k, w, h = 2, 40, 20
    squares = {(1, 6): (7, 3), (0, 0): (1, 1)}  # (quad 1, back node 6) at (7, 3)
    obj = LookupObject(0, "cloth", "", 2, 1, [4, 10], ["1" + "0" * 7, "0" * 6 + "10"],
                       {"front": SideAtlas("f.exr", w, h, {(0, 0): (1, 1)}),
                        "back": SideAtlas("b.exr", w, h, {(1, 6): (7, 3)})})
    for a, b in [(0, 0), (9, 0), (3, 7), (9, 9)]:
        s, t = (a + 0.5) / 10, 1 - (b + 0.5) / 10
        u, v = L.atlas_uv(obj, 1, 1, 6, s, t)
        assert u == pytest.approx((7 + a + 0.5) / w)
        assert v == pytest.approx(1 - (3 + b + 0.5) / h)
    pixels = L.index_pixels(obj, 1, k)  # back side: nodes 4..7 are columns 0..3
    row = 1 * k * k * 4                 # quad 1
    assert pixels[row + 2 * 4: row + 3 * 4] == pytest.approx([7 / w, 1 - (3 + 10) / h, 10, 1])
    assert pixels[row: row + 4] == [0, 0, 0, 1]            # (1, 4) not baked
    assert L.index_pixels(obj, 0, k)[0:4] == pytest.approx([1 / w, 1 - 5 / h, 4, 1])
    # a quad Blender finds degenerate reads as not baked
    assert L.index_pixels(obj, 1, k, hidden={1})[row + 2 * 4: row + 3 * 4] == [0, 0, 0, 1]


def test_degenerate_quad_has_no_frame():
    c = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]
    assert L.corner_frames(c, [(0, 0), (1, 0), (1, 1), (0, 1)]) is None
