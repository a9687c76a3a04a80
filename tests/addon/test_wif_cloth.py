"""clothbake.core.wif_cloth: a WIF cloth as the panel shows and edits it
(the program's draft.json, the palette -> per-thread colours, the drawdown
pixels, the inline spec export writes), and cloth_fields' reading of
weave.wif. The last tests run the program: its drawdown.png against the
panel's pixels, and `clothbake volume` of an edited inline spec."""
import json
import os
import subprocess

import pytest

from clothbake.core import cloth_fields as cf
from clothbake.core import wif_cloth as wc
from clothbake.core.errors import ClothbakeError

RED, GREEN, BLUE = [0.8, 0.05, 0.05], [0.1, 0.6, 0.1], [0.05, 0.1, 0.7]


def small_draft():
    """3 ends x 2 picks: pick 1 = end 1 up only, pick 2 = ends 2 and 3 up;
    warp red, red, blue; weft green, blue."""
    return {"ends": 3, "picks": 2,
            "warp_up": [[1, 0, 0], [0, 1, 1]],
            "warp_colors": [RED, RED, BLUE], "weft_colors": [GREEN, BLUE],
            "palette": [RED, BLUE, GREEN],
            "warp_color_index": [0, 0, 1], "weft_color_index": [2, 1],
            "warp_spacing_mm": [0.5, 0.5, 0.8], "weft_spacing_mm": [0.4, 0.4],
            "warp_width_mm": [0.4, 0.4, 0.4], "weft_width_mm": [0.3, 0.3],
            "source": "x.wif", "source_program": "hand"}


# -- draft.json -----------------------------------------------------------------

def test_a_draft_is_read_and_checked(tmp_path):
    path = tmp_path / "draft.json"
    path.write_text(json.dumps(small_draft()))
    d = wc.read_draft(str(path))
    assert d["ends"] == 3 and d["warp_color_index"] == [0, 0, 1]


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(ends=0), "ends: must be a positive integer"),
    (lambda d: d["warp_up"].pop(), "warp_up: must be an array of 2 rows"),
    (lambda d: d["warp_up"][1].append(0), r"warp_up\[1\]: must be an array of 3 0/1"),
    (lambda d: d["warp_up"][0].__setitem__(0, 2), r"warp_up\[0\]: must be an array of 3 0/1"),
    (lambda d: d["warp_color_index"].__setitem__(2, 3),
     r"warp_color_index\[2\]: must be an index"),
    (lambda d: d["weft_colors"].pop(), "weft_colors: must be an array of 2 colours"),
    (lambda d: d["weft_colors"].__setitem__(0, RED),
     r"weft_colors\[0\]: differs from palette\[2\]"),
    (lambda d: d["warp_spacing_mm"].__setitem__(0, -1),
     "warp_spacing_mm: must be an array of 3 pos"),
    (lambda d: d.update(palette=[]), "palette: must be a non-empty array"),
])
def test_a_bad_draft_names_its_field(change, message):
    d = small_draft()
    change(d)
    with pytest.raises(ClothbakeError, match="d.json: " + message):
        wc.check_draft(d, "d.json")


def test_the_source_program_is_shown_without_the_path():
    assert wc.source_program({"source": "/a/x.wif", "source_program": "/a/x.wif (WeaveIt 2)"}) \
        == "WeaveIt 2"
    assert wc.source_program({"source": "s.json", "source_program": "/a/x.WIF (Tempo (25))"}) \
        == "Tempo (25)"
    assert wc.source_program({"source": "x.wif", "source_program": "hand"}) == "hand"
    assert wc.source_program({}) == ""


def test_the_compact_draft_keeps_the_drawdown():
    c = wc.compact_draft(wc.check_draft(small_draft()))
    assert c["warp_up"] == ["100", "011"]
    assert wc.warp_up_rows(c) == [[True, False, False], [False, True, True]]
    assert json.loads(json.dumps(c)) == c and "warp_colors" not in c


# -- palette and colours ----------------------------------------------------------

def test_editing_a_palette_colour_changes_every_thread_that_uses_it():
    d = small_draft()
    palette = [list(c) for c in d["palette"]]
    assert wc.thread_colors(palette, d["warp_color_index"]) == d["warp_colors"]
    palette[1] = [1.0, 1.0, 0.0]  # blue -> yellow: end 3 and pick 2
    assert wc.thread_colors(palette, d["warp_color_index"]) == [RED, RED, [1.0, 1.0, 0.0]]
    assert wc.thread_colors(palette, d["weft_color_index"]) == [GREEN, [1.0, 1.0, 0.0]]
    assert wc.palette_edited(palette, d["palette"])
    assert not wc.palette_edited(d["palette"], d["palette"])


# -- the drawdown -----------------------------------------------------------------

def test_srgb_encode_is_the_standard_curve():
    assert wc.srgb_encode(0.0) == 0.0 and wc.srgb_encode(1.0) == pytest.approx(1.0)
    assert wc.srgb_encode(0.002) == pytest.approx(0.02584)
    assert wc.srgb_encode(0.214041) == pytest.approx(0.5, abs=1e-5)
    assert wc.srgb_encode(2.0) == pytest.approx(1.0) and wc.srgb_encode(-1) == 0.0


def test_the_drawdown_has_pick_1_at_the_bottom_and_end_1_at_the_left():
    d = small_draft()
    w, h, px = wc.drawdown_pixels(d["warp_up"], d["warp_colors"], d["weft_colors"], block=2)
    assert (w, h) == (6, 4) and len(px) == 6 * 4 * 4

    def at(x, y):  # row 0 is the bottom row (Blender's pixel order)
        i = (y * w + x) * 4
        return px[i:i + 4]

    enc = lambda c: [wc.srgb_encode(x) for x in c] + [1.0]  # noqa: E731
    # pick 1 (bottom two rows): end 1 up (red), ends 2 and 3 down (weft green)
    assert at(0, 0) == at(1, 1) == enc(RED)
    assert at(2, 0) == at(5, 1) == enc(GREEN)
    # pick 2 (top rows): end 1 down (weft blue), end 2 up red, end 3 up blue
    assert at(0, 2) == at(1, 3) == enc(BLUE)
    assert at(2, 3) == enc(RED) and at(4, 3) == enc(BLUE)


def test_block_size_fits_the_long_side():
    assert wc.drawdown_block(4, 4) == 64
    assert wc.drawdown_block(91, 480) == 1 and wc.drawdown_block(2000, 8) == 1
    assert wc.drawdown_block(24, 10) == 10


# -- fields and the inline spec ----------------------------------------------------

def test_a_spec_naming_a_wif_is_the_wif_weave():
    assert cf.fields_from_spec({"weave": {"wif": "a.wif"}})["weave"] == cf.WIF
    with pytest.raises(ClothbakeError, match="c.json: weave: give one of pattern, draft or wif"):
        cf.fields_from_spec({"weave": {"wif": "a.wif", "pattern": "plain"}}, "c.json")
    with pytest.raises(ClothbakeError, match="c.json: weave.wif: must be the path of a WIF"):
        cf.fields_from_spec({"weave": {"wif": ""}}, "c.json")
    with pytest.raises(ClothbakeError, match="weave: the weave is a WIF draft"):
        cf.spec_from_fields(dict(cf.default_fields(), weave=cf.WIF), {})
    base = {"weave": {"wif": "a.wif"}, "density": {"core": 0.7}}
    assert cf.spec_from_fields(dict(cf.default_fields(), weave=cf.WIF), base)["weave"] == \
        base["weave"]


def test_wif_paths_and_specs(tmp_path):
    assert wc.is_wif_path("a/B.WIF") and not wc.is_wif_path("a.json")
    f = tmp_path / "d.wif"
    f.write_text("[WIF]\n")
    assert wc.wif_spec_of_file(str(f)) == {"weave": {"wif": str(f)}}
    with pytest.raises(ClothbakeError, match="cannot read the WIF file"):
        wc.wif_spec_of_file(str(tmp_path / "missing.wif"))
    assert wc.absolute_wif({"weave": {"wif": "../w/d.wif"}}, "/a/b") == "/a/w/d.wif"
    assert wc.absolute_wif({"weave": {"wif": "/x/d.wif"}}, "/a/b") == "/x/d.wif"
    assert wc.absolute_wif({"weave": {"pattern": "plain"}}, "/a") is None


def test_fields_of_a_draft_are_its_means_and_automatic_cells():
    d = small_draft()
    fields = wc.fields_for_draft(cf.default_fields(), d, {"weave": {"wif": "x.wif"}})
    assert fields["warp_spacing_mm"] == pytest.approx(0.6) and fields["weft_width_mm"] == 0.3
    assert (fields["cells_x"], fields["cells_y"]) == (64, 64)  # max(64, 8 x threads)
    big = dict(d, ends=91, picks=480)
    fields = wc.fields_for_draft(cf.default_fields(), big, {"resolution": {"cells_per_thread": 4}})
    assert (fields["cells_x"], fields["cells_y"]) == (364, 1920)
    fields = wc.fields_for_draft(cf.default_fields(), big, {"resolution": {"cells_x": 100}})
    assert fields["cells_x"] == 64  # the spec's own value stays (fields_from_spec read it)
    assert wc.varies(d["warp_spacing_mm"]) and not wc.varies(d["weft_spacing_mm"])


def test_only_the_changed_fields_are_written():
    loaded = cf.default_fields()
    now = dict(loaded, warp_spacing_mm=0.4399999976158142 + 0.0, seed=3)
    now["warp_width_mm"] = 0.4399999976158142  # the float32 of 0.44: unchanged
    assert wc.changed_fields(now, loaded) == {"warp_spacing_mm": now["warp_spacing_mm"],
                                             "seed": 3}


def test_the_inline_spec_of_an_edited_wif_cloth():
    base = {"weave": {"wif": "rel/d.wif"}, "warp": {"color": [1, 0, 0], "twist_deg": 20},
            "density": {"core": 0.7}}
    warp = [[0.1, 0.2, 0.3]] * 3
    weft = [[0.4, 0.5, 0.6000000238418579]] * 2
    spec = wc.inline_spec(base, "/abs/d.wif", {"weft_spacing_mm": 0.30000001192092896,
                                               "seed": 7}, warp, weft)
    assert spec == {"weave": {"wif": "/abs/d.wif"},
                    "warp": {"twist_deg": 20, "colors": warp},
                    "weft": {"spacing_mm": 0.3, "colors": [[0.4, 0.5, 0.6]] * 2},
                    "density": {"core": 0.7}, "seed": 7}
    assert base["weave"]["wif"] == "rel/d.wif"  # the base is not changed
    # colours not edited: no colours written, the file's stay
    assert wc.inline_spec({}, "/abs/d.wif", {}) == {"weave": {"wif": "/abs/d.wif"}}


# -- with the program ---------------------------------------------------------------

# 6 ends x 5 picks, 4 shafts, a 2/1 twill threading broken at end 5, treadled
# with one pick lifting nothing; colours 0-255 with a stripe at end 2 and a
# weft stripe at pick 4.
WIF_TEXT = """[WIF]
Version=1.1
Date=April 20, 1997
Developers=wif@mhsoft.com
Source Program=clothbake test
[CONTENTS]
COLOR PALETTE=yes
WEAVING=yes
WARP=yes
WEFT=yes
COLOR TABLE=yes
THREADING=yes
TIEUP=yes
TREADLING=yes
WARP COLORS=yes
WEFT COLORS=yes
[COLOR PALETTE]
Range=0,255
Entries=3
Form=RGB
[COLOR TABLE]
1=200,30,30
2=20,40,180
3=230,200,60
[WEAVING]
Shafts=3
Treadles=3
Rising Shed=yes
[WARP]
Threads=6
Units=centimeters
Spacing=0.05
Thickness=0.04
Color=1
[WEFT]
Threads=5
Units=centimeters
Spacing=0.05
Thickness=0.04
Color=3
[WARP COLORS]
2=2
[WEFT COLORS]
4=2
[THREADING]
1=1
2=2
3=3
4=1
5=1
6=3
[TIEUP]
1=1,2
2=2,3
3=3,1
[TREADLING]
1=1
2=2
3=3
4=0
5=1
"""


def _draft_command(clothbake_bin):
    """Whether the program lists a draft subcommand (`clothbake draft --help`
    of a program without one prints the main help and exits 0)."""
    out = subprocess.run([clothbake_bin, "--help"], capture_output=True, text=True).stdout
    return any(line.split()[:1] == ["draft"] for line in out.splitlines())


@pytest.fixture
def wif_file(tmp_path):
    path = tmp_path / "twill.wif"
    path.write_text(WIF_TEXT)
    return str(path)


def _png_blocks(path, ends, picks):
    """drawdown.png's colour at each crossing's centre, as [pick][end] (pick 1
    at the image's bottom), 8-bit."""
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    assert spec.width % ends == 0 and spec.height % picks == 0, (spec.width, spec.height)
    bw, bh = spec.width // ends, spec.height // picks
    px = buf.get_pixels(oiio.UINT8)
    return [[list(px[spec.height - 1 - (p * bh + bh // 2), e * bw + bw // 2][:3])
             for e in range(ends)] for p in range(picks)]


def _panel_blocks(d, warp, weft):
    w, h, px = wc.drawdown_pixels(d["warp_up"], warp, weft, 1)
    return [[[round(px[(p * w + e) * 4 + c] * 255) for c in range(3)] for e in range(w)]
            for p in range(h)]


def _assert_same_blocks(a, b):
    assert len(a) == len(b)
    for p, (ra, rb) in enumerate(zip(a, b)):
        for e, (x, y) in enumerate(zip(ra, rb)):
            assert max(abs(int(i) - int(j)) for i, j in zip(x, y)) <= 1, (p, e, x, y)


def test_the_program_draft_and_the_panel_drawdown_agree(clothbake_bin, wif_file, tmp_path):
    assert _draft_command(clothbake_bin), "clothbake draft is not built"
    d, out = wc.run_draft(clothbake_bin, wif_file, str(tmp_path / "cache"))
    assert (d["ends"], d["picks"]) == (6, 5) and wc.source_program(d) == "clothbake test"
    assert d["warp_color_index"] == [0, 1, 0, 0, 0, 0] and len(d["palette"]) == 3
    assert d["weft_color_index"][3] == 1 and d["weft_color_index"][0] == 2
    # colours are display values: 200/255 through the sRGB curve
    assert d["palette"][0][0] == pytest.approx(((200 / 255 + 0.055) / 1.055) ** 2.4, abs=1e-5)
    assert d["warp_up"][3] == [0] * 6  # pick 4 lifts nothing
    assert d["warp_up"][0] == [1, 1, 0, 1, 1, 0]  # treadle 1 lifts shafts 1, 2
    _assert_same_blocks(_png_blocks(os.path.join(out, "drawdown.png"), 6, 5),
                        _panel_blocks(d, d["warp_colors"], d["weft_colors"]))


def test_an_edited_inline_spec_reaches_the_volume(clothbake_bin, wif_file, tmp_path):
    """Palette colour 2 (the blue of end 2 and pick 4) edited: the inline spec's
    draft, drawdown and volume show it at exactly those threads."""
    assert _draft_command(clothbake_bin), "clothbake draft is not built"
    d, _ = wc.run_draft(clothbake_bin, wif_file, str(tmp_path / "cache"))
    palette = [list(c) for c in d["palette"]]
    palette[1] = [0.05, 0.5, 0.2]
    warp = wc.thread_colors(palette, d["warp_color_index"])
    weft = wc.thread_colors(palette, d["weft_color_index"])
    spec = wc.inline_spec({}, wif_file, {}, warp, weft)
    spec_path = tmp_path / "edited.json"
    spec_path.write_text(json.dumps(spec))
    d2, out2 = wc.run_draft(clothbake_bin, str(spec_path), str(tmp_path / "cache"))
    assert d2["warp_up"] == d["warp_up"]
    for got, want in zip(d2["warp_colors"] + d2["weft_colors"], warp + weft):
        assert got == pytest.approx(want, abs=1e-6)
    _assert_same_blocks(_png_blocks(os.path.join(out2, "drawdown.png"), 6, 5),
                        _panel_blocks(d, warp, weft))
    vol = tmp_path / "vol"
    subprocess.run([clothbake_bin, "volume", str(spec_path), "-o", str(vol), "--threads", "1"],
                   check=True, capture_output=True)
    check_crossings(str(vol / "crossings.exr"), d["warp_up"], warp, weft)


def check_crossings(path, warp_up, warp, weft):
    """crossings.exr (x = end, y = pick, row 0 first; A = 1 warp, 2 weft on
    top) against the draft: the top yarn's family, and its colour up to the
    per-cell diffuse factor (colour x a scalar, docs/formats/cloth-spec.md)."""
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    px = buf.get_pixels(oiio.FLOAT)
    assert px.shape[:2] == (len(warp_up), len(warp)), px.shape
    for p, row in enumerate(warp_up):
        for e, up in enumerate(row):
            rgb, family = [float(x) for x in px[p, e, :3]], float(px[p, e, 3])
            assert family == (1.0 if up else 2.0), (p, e, family)
            want = warp[e] if up else weft[p]
            s = sum(a * b for a, b in zip(rgb, want)) / sum(b * b for b in want)
            assert 0.4 < s < 1.2, (p, e, rgb, want)
            assert max(abs(a - s * b) for a, b in zip(rgb, want)) < 0.01, (p, e, rgb, want)


def test_a_scene_s_inline_wif_is_read_relative_to_the_scene(tmp_path, source_dir):
    from clothbake.core.scene import load_scene
    scene = json.load(open(os.path.join(source_dir, "testscenes", "flat", "scene.json")))
    folder = os.path.join(source_dir, "testscenes", "flat")
    for o in scene["objects"]:
        o["mesh"] = os.path.join(folder, o["mesh"])
    scene["objects"][0]["cloth"] = {"weave": {"wif": "drafts/a.wif"}, "seed": 2}
    (tmp_path / "s").mkdir()
    path = tmp_path / "s" / "scene.json"
    path.write_text(json.dumps(scene))
    o = load_scene(str(path))["objects"][0]
    assert o["cloth_wif_path"] == str(tmp_path / "s" / "drafts" / "a.wif")
    assert o["cloth"]["weave"] == {"wif": "drafts/a.wif"}
