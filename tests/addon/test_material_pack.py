"""The material re-packed for Blender (clothbake.core.material_pack): every
texel, view node, level and component at the address the node tree computes,
the periodic gutters, the dense light grid equal to the material's light
factors where its directions are the material's nodes, and refusals."""
import json
import os
import shutil
import subprocess

import numpy as np
import OpenImageIO as oiio
import pytest

from clothbake.core import material_pack as mp
from clothbake.core.errors import ClothbakeError


@pytest.fixture(scope="module")
def material(tmp_path_factory, request):
    source = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    exe = os.environ.get("CLOTHBAKE_BIN", os.path.join(source, "build", "baker", "clothbake"))
    out = str(tmp_path_factory.mktemp("m") / "material")
    # KL = 3 on the plain square: the dense grid of M = 5 holds every node.
    subprocess.run([exe, "material", os.path.join(source, "testscenes", "slab", "scene.json"),
                    "-o", out, "--texels", "4", "--directions", "3", "--light-directions", "3",
                    "--spp", "1", "--light-map", "square", "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)
    return out


def read(path):
    return mp._read_exr(path, "image")


def test_wide_ranks_wrap_into_bands(material, monkeypatch):
    info = mp.read_material(material)
    monkeypatch.setattr(mp, "MAX_WIDTH", 2 * info.k * (info.texels + 2))
    w, h, per_row, band = mp.coefficient_layout(info, 5)
    assert (per_row, w, h) == (2, 2 * info.k * (info.texels + 2), 3 * band)


def test_level_offsets_are_the_running_sum():
    for texels in (1, 2, 8, 32, 1024):
        k = 5
        levels = int(np.log2(texels)) + 1
        running = 0
        for level in range(levels + 1):
            assert mp.level_offset(texels, k, level) == pytest.approx(running, abs=1e-9)
            running += 2 * k * (max(1, texels >> level) + 2)


@pytest.mark.parametrize("one_per_band", [False, True])
def test_every_texel_at_the_node_trees_address(material, monkeypatch, one_per_band):
    info = mp.read_material(material)
    if one_per_band:
        monkeypatch.setattr(mp, "MAX_WIDTH", info.k * (info.texels + 2))
    pack = mp.pack_material(info, rank=64, dense=5)
    assert pack.rank == max(1, info.max_rank)
    coeff, _ = read(pack.coefficients)
    coeff = coeff[::-1]  # row 0 at the bottom, as Blender addresses it
    assert coeff.shape[:2] == (pack.height, pack.width)
    k = info.k
    for level in range(info.levels):
        px, names = read(os.path.join(material, f"level_{level}.exr"))
        s = max(1, info.texels >> level)
        p = s + 2
        y0 = int(round(mp.level_offset(info.texels, k, level)))
        for v in range(2 * k * k):
            row, col = divmod(v, k)        # row = side K + j
            tile_a = px[row * s:(row + 1) * s, col * s:(col + 1) * s, names.index("A")]
            for comp in range(pack.rank):
                tile = np.stack([px[row * s:(row + 1) * s, col * s:(col + 1) * s,
                                    names.index(f"k{comp:04d}.{c}")] for c in "RGB"], -1)
                x0 = ((comp % pack.per_row) * k + col) * p
                yb = (comp // pack.per_row) * pack.band + y0 + row * p
                got = coeff[yb:yb + p, x0:x0 + p]
                # inside: texel (tx, ty) at (1 + tx, 1 + ty); gutter: periodic
                want = np.pad(np.concatenate([tile, tile_a[..., None]], -1),
                              ((1, 1), (1, 1), (0, 0)), mode="wrap")
                np.testing.assert_allclose(got, want, rtol=1e-3, atol=1e-6)


def test_dense_light_grid_holds_the_nodes(material):
    info = mp.read_material(material)
    pack = mp.pack_material(info, rank=64, dense=5)
    lf, names = read(os.path.join(material, "light_factors.exr"))
    dense, _ = read(pack.light_factors)
    dense = dense[::-1]
    k, kl, q = info.k, info.kl, pack.dense + 2
    for v in range(2 * k * k):
        sv, rest = divmod(v, k * k)
        j, i = divmod(rest, k)
        for n in range(2 * kl * kl):
            sl, rest = divmod(n, kl * kl)
            lj, li = divmod(rest, kl)
            a, b = 2 * li, 2 * lj      # M - 1 = 4 = 2 (KL - 1)
            for comp in range(pack.rank):
                g, c = divmod(comp, 4)
                x = ((g * k + i) * 2 + sl) * q + 1 + a
                y = (sv * k + j) * q + 1 + b
                assert dense[y, x, c] == pytest.approx(lf[v, n, names.index(f"k{comp:04d}")],
                                                       rel=1e-5, abs=1e-7)


@pytest.mark.parametrize("light_map", [mp.HORIZON, mp.SQUARE])
def test_world_weights_integrate_the_hemisphere(light_map):
    """Exact limits: factors of 1 on every node of a side integrate to that
    hemisphere's 2 pi (Catmull-Rom weights sum to 1, the lattice's areas to
    2 pi), nothing from the other side; factors equal to the node's cosine
    |z| integrate to pi, up to the interpolation between 16 x 16 nodes."""
    kl = 16
    w = mp.world_weights(kl, light_map, samples=1 << 14)
    n = kl * kl
    for side in (0, 1):
        ones = np.zeros(2 * n)
        ones[side * n:(side + 1) * n] = 1.0
        assert w[side] @ ones == pytest.approx(2 * np.pi, rel=1e-12)
        assert w[1 - side] @ ones == pytest.approx(0.0, abs=1e-12)
    g = np.arange(kl) / (kl - 1)
    u, v = np.meshgrid(g, g)       # node (i, j) at index j kl + i
    if light_map == mp.HORIZON:
        u, v = mp.horizon_from_grid(u, v)
    z = mp.hemi_oct_decode(u, v)[..., 2].reshape(-1)
    cosine = np.concatenate([z, z])
    assert w[0] @ cosine == pytest.approx(np.pi, rel=5e-3)
    assert w[1] @ cosine == pytest.approx(np.pi, rel=5e-3)


def test_world_factors_at_the_node_trees_address(material):
    """Each view node's world factors, its own hemisphere (ws 0) and the
    other (ws 1), where material_nodes.lights.world_terms reads them."""
    info = mp.read_material(material)
    pack = mp.pack_material(info, rank=64, dense=5)
    lf, names = read(os.path.join(material, "light_factors.exr"))
    dense, _ = read(pack.light_factors)
    dense = dense[::-1]
    k, q = info.k, pack.dense + 2
    assert dense.shape[:2] == (pack.light_height, pack.light_width) == \
        (2 * k * q + 2 * k, pack.groups * k * 2 * q)
    w = mp.world_weights(info.kl, info.light_map)
    for v in range(2 * k * k):
        sv, rest = divmod(v, k * k)
        j, i = divmod(rest, k)
        for comp in range(pack.rank):
            g, c = divmod(comp, 4)
            f = lf[v, :, names.index(f"k{comp:04d}")].astype(np.float64)
            for ws in (0, 1):
                x = ((g * k + i) * 2 + ws) * q + 1
                want = w[sv if ws == 0 else 1 - sv] @ f
                assert dense[2 * k * q + sv * k + j, x, c] == pytest.approx(
                    want, rel=1e-5, abs=1e-7)


@pytest.mark.parametrize("light_map", [mp.HORIZON, mp.SQUARE])
def test_catmull_rom_weights_sum_to_one(light_map):
    rng = np.random.default_rng(1)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    w = mp.light_node_weights(d, 10, light_map)
    np.testing.assert_allclose(w.sum(1), 1.0, atol=1e-9)
    side = (d[:, 2] < 0)
    assert np.all(w[side, :100] == 0) and np.all(w[~side, 100:] == 0)


def test_pack_is_reused_and_remade(material):
    info = mp.read_material(material)
    first = mp.pack_material(info, rank=1, dense=4)
    stamp = os.stat(first.coefficients).st_mtime_ns
    again = mp.pack_material(mp.read_material(material), rank=1, dense=4)
    assert os.stat(again.coefficients).st_mtime_ns == stamp
    with open(os.path.join(first.folder, "pack.json")) as f:
        meta = json.load(f)
    meta["key"] = "stale"
    with open(os.path.join(first.folder, "pack.json"), "w") as f:
        json.dump(meta, f)
    remade = mp.pack_material(info, rank=1, dense=4)
    with open(os.path.join(remade.folder, "pack.json")) as f:
        assert json.load(f)["key"] == mp.pack_key(info, 1, 4)
    assert not [n for n in os.listdir(material) if ".tmp-" in n or ".old-" in n]


@pytest.mark.parametrize("field,value,text", [
    ("format", "clothbake-lookup", "format"),
    ("texels", 3, "texels"),
    ("ranks", [1, 2], "ranks"),
    ("directions", 1, "directions"),
    ("light_direction_map", "polar", "light_direction_map"),
    ("parallax_depth_mm", -0.01, "parallax_depth_mm"),
    ("parallax_depth_mm", 100.0, "parallax_depth_mm"),
])
def test_bad_manifest_names_the_field(material, tmp_path, field, value, text):
    bad = tmp_path / "bad"
    shutil.copytree(material, bad)
    path = bad / "manifest.json"
    m = json.loads(path.read_text())
    m[field] = value
    path.write_text(json.dumps(m))
    with pytest.raises(ClothbakeError) as e:
        mp.read_material(str(bad))
    assert e.value.field == text and str(path) in str(e.value)


def test_missing_image_is_named(material, tmp_path):
    bad = tmp_path / "bad"
    shutil.copytree(material, bad)
    os.remove(bad / "level_1.exr")
    with pytest.raises(ClothbakeError) as e:
        mp.read_material(str(bad))
    assert "level_1.exr" in str(e.value)


@pytest.fixture(scope="module")
def addressed(tmp_path_factory):
    """A material addressed per crossing of a real WIF (Mac WeaveIt's 62 x
    62 twill, 30 classes of crossings), at tiny settings."""
    source = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    exe = os.environ.get("CLOTHBAKE_BIN", os.path.join(source, "build", "baker", "clothbake"))
    work = tmp_path_factory.mktemp("a")
    spec = work / "cloth.json"
    spec.write_text(json.dumps({"name": "twill", "weave": {"wif": os.path.join(
        source, "testscenes", "wif", "real", "wi_32twill.wif")}}))
    out = str(work / "addressed")
    subprocess.run([exe, "material", str(spec), "-o", out, "--address", "crossings",
                    "--texels", "2", "--directions", "2", "--light-directions", "2", "--spp", "1",
                    "--context", "1", "--quiet"], check=True, stdout=subprocess.DEVNULL)
    return out


def test_addressed_blocks_at_the_node_trees_address(addressed):
    """Every crossing's texels, at every level, view node and component, at
    the address material_nodes.address.crossing_address computes from the packed
    index: the block of the crossing's class, in the tile's grid of blocks."""
    info = mp.read_material(addressed)
    assert info.address == mp.CROSSINGS and (info.ends, info.picks, info.blocks) == (62, 62, 30)
    bx, by = info.block_grid
    assert (bx, by) == (6, 5)
    pack = mp.pack_material(info, rank=64, dense=5)
    coeff = read(pack.coefficients)[0][::-1]     # row 0 at the bottom
    nxt = read(pack.next_coefficients)[0][::-1]
    index = read(pack.crossings)[0][::-1]
    block_of, names = read(info.crossings_file)
    block_of = block_of[..., names.index("block")]               # [pick, end]
    np.testing.assert_array_equal(index[..., 0], block_of)
    assert sorted(set(block_of.ravel().astype(int))) == list(range(info.blocks))
    k = info.k
    rng = np.random.default_rng(3)
    crossings = [(int(e), int(p)) for e, p in rng.integers(0, 62, (40, 2))]
    for level in range(info.levels):
        px, ch = read(os.path.join(addressed, f"level_{level}.exr"))
        s = max(1, info.texels >> level)
        pitch_x, pitch_y = bx * s + 2, by * s + 2
        y_level = mp.level_offset(info.texels, k, level, by)
        for v in range(2 * k * k):
            row, col = divmod(v, k)
            for comp in range(pack.rank):
                for e, p in crossings:
                    b, gx, gy, _ = index[p, e]
                    for ix in range(s):
                        for iy in range(s):
                            # the node tree's pixel centre, as _crossing_address
                            x = ((comp % pack.per_row) * k + col) * pitch_x + gx * s + ix + 1.5
                            y = (comp // pack.per_row) * pack.band + y_level + \
                                row * pitch_y + gy * s + iy + 1.5
                            got = coeff[int(y), int(x)]
                            fy = (row * info.blocks + int(b)) * s + iy
                            fx = col * s + ix
                            want = [px[fy, fx, ch.index(f"k{comp:04d}.{c}")]
                                    for c in ("specular", "warp", "weft")] + \
                                [px[fy, fx, ch.index("A")]]
                            np.testing.assert_allclose(got, want, rtol=1e-3, atol=1e-6)
                            np.testing.assert_allclose(
                                nxt[int(y), int(x), :2],
                                [px[fy, fx, ch.index(f"k{comp:04d}.{c}")]
                                 for c in ("warp_next", "weft_next")], rtol=1e-3, atol=1e-6)


def test_addressed_on_uneven_threads_packs_their_spans(addressed, tmp_path):
    """Threads of their own spacings: the pack writes the span image the
    nodes place a point with, one row a family, from the manifest's
    centres; evenly spaced ones need none."""
    assert mp.read_material(addressed).even == (True, True)
    assert not mp.pack_material(mp.read_material(addressed), rank=1, dense=3).spans
    bad = tmp_path / "uneven"
    shutil.copytree(addressed, bad)
    shutil.rmtree(bad / "blender-r1-m3", ignore_errors=True)
    path = bad / "manifest.json"
    m = json.loads(path.read_text())
    m["cloth"]["threads"]["weft"]["centres_mm"][1] += 0.2
    path.write_text(json.dumps(m))
    info = mp.read_material(str(bad))
    assert info.even == (True, False)
    pack = mp.pack_material(info, rank=1, dense=3)
    spans = read(pack.spans)[0][::-1]        # row 0 at the bottom: the warp's
    for row, family in enumerate(("warp", "weft")):
        want = mp.span_pixels(info.centres_mm[family], info.repeat_mm[row])
        np.testing.assert_allclose(spans[row], want, rtol=1e-6)


def test_span_image_places_a_point_among_uneven_threads():
    """material_pack.span_pixels for threads of their own spacings (a real
    WIF's: d2w_zeros.wif's five ends, mm): the crossing coordinate the nodes
    compute from a Closest read, e + (u - start) / span, equals the exact
    one (thread j's span between the midpoints to its neighbours, j + the
    fraction across it) to within a sample's width times the two widths'
    difference, and exactly inside every span away from its ends."""
    centres = [1.06, 3.18, 4.77, 5.83, 6.36]
    repeat = 7.42
    width = 1024
    px = mp.span_pixels(centres, repeat, width)
    c = np.array(centres) / repeat
    ext = np.concatenate([[c[-1] - 1], c, [c[0] + 1]])
    bounds = np.concatenate([0.5 * (ext[:-1] + ext[1:])])          # span ends of threads -1 .. n
    u = (np.arange(width) + 0.5) / width
    j = np.searchsorted(bounds, u, side="right") - 1               # thread index (0 .. n)
    exact = j + (u - bounds[j]) / (bounds[j + 1] - bounds[j])
    got = px[:, 0] + (u - px[:, 1]) * px[:, 2]
    spans = np.diff(bounds)
    slack = (1.0 / width) * (1 / spans.min() - 1 / spans.max())
    assert np.max(np.abs(got - exact)) <= slack + 1e-5
    # the stored thread is the exact one (the samples are their pixels' centres)
    np.testing.assert_array_equal(px[:, 0], j)
