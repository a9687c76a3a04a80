"""A colour-free material's yarn colours (clothbake.core.yarn_colours) and its
version-2 manifest (clothbake.core.material_manifest, material_pack): the
colour strips exact for a 2-colour stripe of equal spacing (a boundary texel
half on each thread, the wrap at the origin), the owner + 1 / - 1 strips,
every level the pairwise box average of the one below, q repeats and
periodicity, against a brute-force integral for uneven threads; the view
nodes' next sides as the program's float32 decode gives them; a version-2
manifest read and refused field by field; a colour-free folder packed with
its next atlas."""
import json
import os

import numpy as np
import OpenImageIO as oiio
import pytest

from clothbake.core import material_pack as mp
from clothbake.core import yarn_colours as yc
from clothbake.core.directions import hemi_oct_decode
from clothbake.core.errors import ClothbakeError
from clothbake.core.material_manifest import SWF, read_material

A, B, C = [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]


def test_stripe_boundary_texel_is_half_each_thread():
    # Threads at 0.125 and 0.625 of a 1 mm repeat: thread 0 owns [0.875 - 1,
    # 0.375), thread 1 [0.375, 0.875); 4 texels of 0.25 mm.
    levels = yc.colour_strip([0.125, 0.625], 1.0, [A, B], 4, 3)
    np.testing.assert_array_equal(levels[0], [A, [0.5, 0, 0.5], B, [0.5, 0, 0.5]])
    np.testing.assert_array_equal(levels[1], [[0.75, 0, 0.25], [0.25, 0, 0.75]])
    np.testing.assert_array_equal(levels[2], [[0.5, 0, 0.5]])


def test_thread_across_the_origin_wraps():
    # Thread 0 centred on x = 0 owns [-0.25, 0.25) and [0.75, 1.0).
    levels = yc.colour_strip([0.0, 0.5], 1.0, [A, B], 4, 3)
    np.testing.assert_array_equal(levels[0], [A, B, B, A])
    levels = yc.colour_strip([0.0, 0.5], 1.0, [A, B], 2, 2)
    np.testing.assert_array_equal(levels[0], [[0.5, 0, 0.5]] * 2)


def test_plus_and_minus_take_the_neighbours_colours():
    own, plus, minus = yc.family_strips([0.25, 0.75], 1.0, [A, B, C], 4, 3)
    assert len(own[0]) == 3 * 4                      # q = lcm(2, 3) / 2 = 3
    # threads 0..5 over the 3 repeats: A B C A B C, two texels each
    np.testing.assert_array_equal(own[0], np.repeat([A, B, C, A, B, C], 2, axis=0))
    np.testing.assert_array_equal(plus[0], np.repeat([B, C, A, B, C, A], 2, axis=0))
    np.testing.assert_array_equal(minus[0], np.repeat([C, A, B, C, A, B], 2, axis=0))


@pytest.mark.parametrize("threads,sequence,q", [(2, 1, 1), (2, 12, 6), (4, 6, 3), (5, 5, 1),
                                                (2, 480, 240), (3, 48, 16)])
def test_repeats(threads, sequence, q):
    assert yc.strip_repeats(threads, sequence) == q


def test_levels_are_pairwise_box_averages_and_periodic():
    rng = np.random.default_rng(3)
    centres = np.sort(rng.uniform(0, 0.9, 3)) + [0.0, 0.02, 0.05]
    colours = rng.uniform(0, 1, (4, 3))
    levels = yc.colour_strip(centres, 0.9, colours, 8, 4)       # q = lcm(3, 4) / 3 = 4
    assert [len(x) for x in levels] == [32, 16, 8, 4]
    for fine, coarse in zip(levels, levels[1:]):
        np.testing.assert_allclose(coarse, 0.5 * (fine[0::2] + fine[1::2]), rtol=0, atol=1e-15)
    # Shifting the sequence by one repeat's threads rolls the strip by one repeat.
    rolled = yc.colour_strip(centres, 0.9, np.roll(colours, -3, axis=0), 8, 1)[0]
    np.testing.assert_allclose(rolled, np.roll(levels[0], -8, axis=0), atol=1e-12)
    # Level 0 against a brute-force average of the owner's colour at many points.
    x = (np.arange(32 * 4096) + 0.5) / (32 * 4096) * 4 * 0.9
    all_centres = np.concatenate([centres + r * 0.9 for r in range(-1, 5)])
    owner = np.abs(x[:, None] - all_centres[None, :]).argmin(1) - 3   # thread index j
    brute = colours[(owner % 12) % 4].reshape(32, 4096, 3).mean(1)
    np.testing.assert_allclose(levels[0], brute, atol=2e-3)


def test_plain_family_is_its_colour_everywhere():
    for strip in yc.family_strips([0.1, 0.3, 0.5], 0.6, [[0.2, 0.4, 0.6]], 4, 3):
        for level in strip:
            np.testing.assert_allclose(level, [[0.2, 0.4, 0.6]] * len(level), atol=1e-15)


def test_strip_pixels_layout():
    strips = yc.family_strips([0.25, 0.75], 1.0, [A, B, C], 4, 3)
    width, rows, height = yc.strip_layout(3, 4, 3)
    assert (width, rows, height) == (12, 1, 9)
    px = yc.strip_pixels(strips, width, rows)
    assert px.shape == (9, 12, 4)
    for b in range(3):
        for m in range(3):
            row = strips[b][m]
            np.testing.assert_allclose(px[b * 3 + m, :len(row), :3], row)
            assert not px[b * 3 + m, len(row):, :3].any()
    assert (px[..., 3] == 1).all()


def test_wide_strips_fold_into_rows(monkeypatch):
    monkeypatch.setattr(yc, "MAX_STRIP_WIDTH", 5)
    strips = yc.family_strips([0.25, 0.75], 1.0, [A, B, C], 4, 3)
    width, rows, height = yc.strip_layout(3, 4, 3)
    assert (width, rows, height) == (5, 3, 27)
    px = yc.strip_pixels(strips, width, rows)
    for b in range(3):
        for m in range(3):
            for c, colour in enumerate(strips[b][m]):
                np.testing.assert_allclose(px[(b * 3 + m) * rows + c // 5, c % 5, :3], colour)


def test_next_sides_follow_the_view_rays():
    k = 8
    sides = yc.next_sides(k)
    assert sides.shape == (2 * k, k, 2)
    np.testing.assert_array_equal(sides[:k], sides[k:])
    g = np.arange(k) / (k - 1)
    u, v = np.meshgrid(g, g)
    d = hemi_oct_decode(u, v)
    ray = -d
    off_x = np.abs(d[..., 0]) > 1e-6
    off_y = np.abs(d[..., 1]) > 1e-6
    np.testing.assert_array_equal(sides[:k, :, 0][off_x], (ray[..., 0] >= 0)[off_x])
    np.testing.assert_array_equal(sides[:k, :, 1][off_y], (ray[..., 1] >= 0)[off_y])
    # On the diagonal i + j = K - 1 (d.x = 0 exactly) the program's float32
    # decode gives px = 0 at the ends and +3e-8 in the middle for K = 8
    # (no FMA in its build): owner + 1 where 0, owner - 1 where not, so
    # lookup-render and Blender pick the same neighbour. sides[side K + j, i].
    assert [sides[7 - i, i, 0] for i in range(k)] == [1, 1, 0, 0, 0, 0, 1, 1]


# --- a version-2 folder -------------------------------------------------------

K, TEXELS, LEVELS = 2, 2, 2


def _write(path, channels, width, height, values):
    spec = oiio.ImageSpec(width, height, len(channels), oiio.FLOAT)
    spec.channelnames = tuple(channels)
    out = oiio.ImageOutput.create(path)
    assert out.open(path, spec)
    out.write_image(np.ascontiguousarray(values, np.float32))
    out.close()


def _folder(tmp_path, version=2, parts=SWF, cloth_extra=None):
    folder = tmp_path / "m"
    folder.mkdir(exist_ok=True)
    channels = ["A"] + [f"k0000.{c}" for c in
                        (("specular", "warp", "weft", "warp_next", "weft_next") if parts == SWF
                         else "RGB")]
    for m in range(LEVELS):
        s = max(1, TEXELS >> m)
        h, w = 2 * K * s, K * s
        values = np.zeros((h, w, len(channels)))
        values[..., 0] = 1.0
        for c in range(1, len(channels)):
            values[..., c] = c + 10 * m + 0.25 * np.arange(w)[None, :] + 0.5 * np.arange(h)[:, None]
        _write(str(folder / f"level_{m}.exr"), channels, w, h, values)
    _write(str(folder / "light_factors.exr"), ["k0000"], 2 * K * K, 2 * K * K,
           np.ones((2 * K * K, 2 * K * K, 1)))
    cloth = {"name": "c", "hash": "0123456789abcdef"}
    if parts == SWF:
        cloth.update({"threads": {"warp": {"centres_mm": [0.25, 0.75]},
                                  "weft": {"centres_mm": [0.5]}},
                      "colors": {"warp": {"color": [0.6, 0.1, 0.1]},
                                 "weft": {"color": [0.5, 0.4, 0.1], "colors": [A, B]}}})
    cloth.update(cloth_extra or {})
    m = {"format": "clothbake-material", "version": version, "texels": TEXELS, "levels": LEVELS,
         "directions": K, "light_directions": K, "direction_map": "hemi-octahedral",
         "light_direction_map": "hemi-octahedral", "max_rank": 1, "ranks": [1] * (2 * K * K),
         "repeat_mm": [1.0, 1.0, 0.3], "optics": {"depth_scale": 1.0}, "cloth": cloth,
         "files": {"levels": [f"level_{m}.exr" for m in range(LEVELS)],
                   "light_factors": "light_factors.exr"}}
    if version == 2:
        m["parts"] = parts
    (folder / "manifest.json").write_text(json.dumps(m))
    return str(folder)


def test_version_2_manifest(tmp_path):
    info = read_material(_folder(tmp_path))
    assert info.parts == SWF
    assert info.channels == ("specular", "warp", "weft", "warp_next", "weft_next")
    assert info.centres_mm == {"warp": [0.25, 0.75], "weft": [0.5]}
    assert info.colors["warp"] == {"color": [0.6, 0.1, 0.1], "colors": []}
    assert info.colors["weft"]["colors"] == [A, B]
    assert info.written_repeats == (1.0, 1.0)  # absent: a draft written once
    # A WIF written over its colour repeat is baked over its weave's.
    info = read_material(_folder(tmp_path, cloth_extra={"written_repeats": [107, 2]}))
    assert info.written_repeats == (107.0, 2.0)


def test_version_1_and_rgb_parts(tmp_path):
    assert read_material(_folder(tmp_path, version=1, parts="rgb")).parts == "rgb"
    info = read_material(_folder(tmp_path, version=2, parts="rgb"))
    assert info.parts == "rgb" and info.channels == ("R", "G", "B") and info.centres_mm is None


@pytest.mark.parametrize("change,field", [
    ({"threads": {"warp": {"centres_mm": [0.75, 0.25]}, "weft": {"centres_mm": [0.5]}}},
     "cloth.threads.warp.centres_mm"),
    ({"threads": {"warp": {"centres_mm": [0.25, 1.5]}, "weft": {"centres_mm": [0.5]}}},
     "cloth.threads.warp.centres_mm"),
    ({"threads": {"warp": {"centres_mm": [0.25]}}}, "cloth.threads.weft.centres_mm"),
    ({"written_repeats": [0.5, 1]}, "cloth.written_repeats"),
    ({"written_repeats": [2]}, "cloth.written_repeats"),
    ({"colors": {"warp": {"color": [1, 2]}, "weft": {"color": [0, 0, 0]}}},
     "cloth.colors.warp.color"),
    ({"colors": {"warp": {"color": [1, 1, 1]}, "weft": {"color": [0, 0, 0], "colors": [[1]]}}},
     "cloth.colors.weft.colors"),
])
def test_version_2_refusals(tmp_path, change, field):
    with pytest.raises(ClothbakeError, match=field.replace(".", r"\.")):
        read_material(_folder(tmp_path, cloth_extra=change))


def test_unknown_parts_and_versions_refused(tmp_path):
    with pytest.raises(ClothbakeError, match="parts"):
        read_material(_folder(tmp_path, parts="spectral"))
    with pytest.raises(ClothbakeError, match="version"):
        read_material(_folder(tmp_path, version=4))


def test_colour_free_pack_puts_the_next_parts_beside(tmp_path):
    info = read_material(_folder(tmp_path))
    pack = mp.pack_material(info, rank=1, dense=3)
    assert pack.next_coefficients and os.path.isfile(pack.next_coefficients)
    coeff = mp._read_exr(pack.coefficients, "c")[0][::-1]
    nxt = mp._read_exr(pack.next_coefficients, "n")[0][::-1]
    sides = yc.next_sides(K)
    for m in range(LEVELS):
        s = max(1, TEXELS >> m)
        level, names = mp._read_exr(os.path.join(info.folder, f"level_{m}.exr"), "l")
        y0 = int(round(mp.level_offset(TEXELS, K, m)))
        for row in range(2 * K):
            for col in range(K):
                for ty in range(s):
                    for tx in range(s):
                        src = level[row * s + ty, col * s + tx]
                        got = coeff[y0 + row * (s + 2) + 1 + ty, col * (s + 2) + 1 + tx]
                        gn = nxt[y0 + row * (s + 2) + 1 + ty, col * (s + 2) + 1 + tx]
                        want = [src[names.index(f"k0000.{c}")] for c in info.channels]
                        np.testing.assert_allclose(got[:3], want[:3], rtol=1e-3)
                        np.testing.assert_allclose(gn[:2], want[3:], rtol=1e-3)
                        np.testing.assert_array_equal(gn[2:], sides[row, col])
