"""A cloth woven from a WIF draft (a weaver's own draft file, the format
weaving programs share), as the panel shows and edits it:
the program's reading of the draft (`clothbake draft INPUT -o DIR` writes
DIR/draft.json, docs/formats/wif.md), its drawdown as preview pixels, the
palette of distinct colours an artist edits, and the inline spec export writes
once something is edited.

The panel never reads the WIF itself: the program is the one reader. What the
panel keeps per object (`compact_draft`) is enough to redraw the drawdown in
any colours and to write the spec, without the program or its cache.

The drawdown is recoloured here, in Python, rather than by running the program
again on every edit: a colour field calls its update on every step of a drag
in the colour picker, and a recolouring is a table look-up per crossing (a few
milliseconds for a 91 x 480 draft) where a program run is a process start and a
WIF parse per step. The tests hold the two drawdowns equal
(tests/addon/test_wif_cloth.py, tests/blender/ui_wif_panel.py).
"""
import copy
import hashlib
import json
import os
import re

from . import program as runner
from .cloth_fields import FIELDS, COLOR_FIELDS, INT_FIELDS, short_float
from .errors import ClothbakeError

# Preview: blocks of BLOCK_TARGET // max(ends, picks) pixels per crossing (at
# least 1), so a small draft is drawn as sharp blocks and a large one at one
# pixel per crossing.
BLOCK_TARGET = 256
# resolution.cells_per_thread when a spec does not set it (cloth_spec.h).
CELLS_PER_THREAD = 8


def is_wif_path(path):
    """Whether `path` names a WIF file (by its extension, as the program decides)."""
    return os.path.splitext(str(path))[1].lower() == ".wif"


def spec_wif(spec):
    """The weave.wif of a cloth spec dict as written (None when it has none)."""
    weave = spec.get("weave") if isinstance(spec, dict) else None
    return weave.get("wif") if isinstance(weave, dict) else None


def wif_spec_of_file(path):
    """The cloth spec a .wif file stands for: {"weave": {"wif": ABSOLUTE_PATH}}.
    Raises ClothbakeError when the file cannot be read."""
    path = os.path.abspath(path)
    try:
        with open(path, "rb"):
            pass
    except OSError as e:
        raise ClothbakeError(f"cannot read the WIF file: {e.strerror}", path) from None
    return {"weave": {"wif": path}}


def absolute_wif(spec, folder):
    """The absolute path of a spec's weave.wif, relative paths read from
    `folder` (the spec file's folder, or the scene's for an inline spec)."""
    wif = spec_wif(spec)
    if not isinstance(wif, str) or not wif:
        return None
    return os.path.normpath(os.path.join(folder, wif))


# -- the program's draft.json -------------------------------------------------

def _rgb_list(value, count, path, field):
    if not isinstance(value, list) or len(value) != count:
        raise ClothbakeError(f"must be an array of {count} colours", path, field)
    out = []
    for i, c in enumerate(value):
        if (not isinstance(c, list) or len(c) != 3 or
                not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in c)):
            raise ClothbakeError("must be an array of 3 numbers", path, f"{field}[{i}]")
        out.append([float(x) for x in c])
    return out


def _index_list(value, count, palette_size, path, field):
    if not isinstance(value, list) or len(value) != count:
        raise ClothbakeError(f"must be an array of {count} integers", path, field)
    for i, x in enumerate(value):
        if not isinstance(x, int) or isinstance(x, bool) or not 0 <= x < palette_size:
            raise ClothbakeError(f"must be an index into the palette (0..{palette_size - 1})",
                                 path, f"{field}[{i}]")
    return list(value)


def check_draft(d, path=""):
    """A draft.json dict checked against the contract; returns it with the
    lists as plain Python lists. Raises ClothbakeError naming the field."""
    if not isinstance(d, dict):
        raise ClothbakeError("a draft must be a JSON object", path)
    for key in ("ends", "picks"):
        if not isinstance(d.get(key), int) or isinstance(d.get(key), bool) or d[key] < 1:
            raise ClothbakeError("must be a positive integer", path, key)
    ends, picks = d["ends"], d["picks"]
    up = d.get("warp_up")
    if not isinstance(up, list) or len(up) != picks:
        raise ClothbakeError(f"must be an array of {picks} rows (one per pick)", path, "warp_up")
    for p, row in enumerate(up):
        if not isinstance(row, list) or len(row) != ends or any(x not in (0, 1) or
                                                                 isinstance(x, bool)
                                                                 for x in row):
            raise ClothbakeError(f"must be an array of {ends} 0/1 values", path, f"warp_up[{p}]")
    palette = d.get("palette")
    if not isinstance(palette, list) or not palette:
        raise ClothbakeError("must be a non-empty array of colours", path, "palette")
    palette = _rgb_list(palette, len(palette), path, "palette")
    out = dict(d)
    out["palette"] = palette
    out["warp_color_index"] = _index_list(d.get("warp_color_index"), ends, len(palette), path,
                                          "warp_color_index")
    out["weft_color_index"] = _index_list(d.get("weft_color_index"), picks, len(palette), path,
                                          "weft_color_index")
    for family, count in (("warp", ends), ("weft", picks)):
        colors = _rgb_list(d.get(f"{family}_colors"), count, path, f"{family}_colors")
        indices = out[f"{family}_color_index"]
        for i, c in enumerate(colors):  # the palette and indices say the same
            if max(abs(a - b) for a, b in zip(c, palette[indices[i]])) > 1e-4:
                raise ClothbakeError(f"differs from palette[{indices[i]}]", path,
                                     f"{family}_colors[{i}]")
        out[f"{family}_colors"] = colors
        for key in (f"{family}_spacing_mm", f"{family}_width_mm"):
            v = d.get(key)
            if v is None:
                continue
            if not isinstance(v, list) or len(v) != count or not all(
                    isinstance(x, (int, float)) and not isinstance(x, bool) and x > 0 for x in v):
                raise ClothbakeError(f"must be an array of {count} positive numbers", path, key)
    for key in ("source", "source_program"):
        if key in d and not isinstance(d[key], str):
            raise ClothbakeError("must be a string", path, key)
    return out


def read_draft(path):
    """DIR/draft.json as written by `clothbake draft`, checked."""
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except OSError as e:
        raise ClothbakeError(f"cannot read the draft: {e.strerror}", path) from None
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ClothbakeError(f"invalid JSON: {e}", path) from None
    return check_draft(d, path)


def cache_dir(root, input_path):
    """Where the draft of `input_path` goes: one folder per input file under
    ROOT/clothbake_draft, so reloading a file replaces its own output."""
    key = hashlib.sha256(os.path.abspath(input_path).encode()).hexdigest()[:12]
    stem = os.path.splitext(os.path.basename(input_path))[0] or "cloth"
    return os.path.join(root, "clothbake_draft", f"{stem}-{key}")


def run_draft(program, input_path, cache_root):
    """Runs `clothbake draft INPUT -o DIR` (INPUT a .wif or a cloth spec JSON)
    and returns (the checked draft, DIR). Raises ClothbakeError with the
    program's message when it refuses the input."""
    out = cache_dir(cache_root, input_path)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    runner.run([program, "draft", os.path.abspath(input_path), "-o", out], "draft")
    return read_draft(os.path.join(out, "draft.json")), out


def write_spec_for_draft(spec, wif_path, cache_root, name):
    """An inline spec (from a scene) written where `clothbake draft` can read
    it, weave.wif made absolute. Returns the file's path."""
    spec = copy.deepcopy(spec)
    spec["weave"] = {"wif": wif_path}
    folder = os.path.join(cache_root, "clothbake_draft")
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"{name or 'cloth'}-inline.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(spec, f)
    return path


# -- what the panel keeps -------------------------------------------------------

def compact_draft(d):
    """The part of a checked draft the object keeps (JSON-able, small: the
    drawdown as one '0'/'1' string per pick)."""
    keep = {k: d[k] for k in ("ends", "picks", "palette", "warp_color_index",
                              "weft_color_index") }
    keep["warp_up"] = ["".join("1" if x else "0" for x in row) for row in d["warp_up"]]
    for key in ("source", "source_program", "warp_spacing_mm", "weft_spacing_mm",
                "warp_width_mm", "weft_width_mm"):
        if key in d:
            keep[key] = d[key]
    return keep


def warp_up_rows(compact):
    """The compact drawdown back as lists of bools, row p = pick p + 1."""
    return [[c == "1" for c in row] for row in compact["warp_up"]]


def source_program(draft):
    """The program that wrote the WIF, as draft.json's source_program gives
    it ("WIF_PATH (PROGRAM)": the path left out), or ""."""
    text = (draft.get("source_program") or "").strip()
    m = re.match(r"^.*\.wif \((.*)\)$", text, re.IGNORECASE | re.DOTALL)
    return m.group(1).strip() if m else text


def thread_colors(palette, indices):
    """Per-thread colours from the (edited) palette: thread i takes
    palette[indices[i]], so editing one palette colour recolours every
    thread that uses it."""
    return [list(palette[i]) for i in indices]


def palette_edited(palette, loaded, tol=0.0):
    """Whether any palette colour differs from the one loaded."""
    return any(abs(a - b) > tol for c, l in zip(palette, loaded) for a, b in zip(c, l))


# -- the drawdown as preview pixels ---------------------------------------------

def srgb_encode(c):
    """Linear -> display sRGB (IEC 61966-2-1), clamped to [0, 1]."""
    c = min(max(float(c), 0.0), 1.0)
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1.0 / 2.4) - 0.055


def drawdown_block(ends, picks, target=BLOCK_TARGET):
    """Pixels per crossing of the preview."""
    return max(1, target // max(ends, picks))


def drawdown_pixels(warp_up, warp_colors, weft_colors, block=1):
    """The drawdown as flat RGBA floats in display sRGB, the layout Blender's
    ImagePreview.image_pixels_float takes: row 0 at the BOTTOM is pick 1
    (as weavers draw it, and as drawdown.png shows it with its row 0 at the
    top the last pick), column 0 end 1; each crossing a block x block square
    in the colour of the thread on top. Returns (width, height, pixels)."""
    picks, ends = len(warp_up), len(warp_colors)
    warp_px = [[srgb_encode(x) for x in c] + [1.0] for c in warp_colors]
    weft_px = [[srgb_encode(x) for x in c] + [1.0] for c in weft_colors]
    pixels = []
    for p in range(picks):
        row = []
        weft = weft_px[p]
        for e, up in enumerate(warp_up[p]):
            row.extend((warp_px[e] if up else weft) * block)
        for _ in range(block):
            pixels.extend(row)
    return ends * block, picks * block, pixels


# -- the panel's fields for a WIF cloth, and the spec export writes -------------

def fields_for_draft(fields, draft, spec):
    """The panel's fields of a WIF cloth: `fields` (from the spec, defaults
    where it is silent) with what the program read from the draft: the mean
    spacing and width of each family (one field stands for the per-thread
    values; editing it sets every thread's), and, where the spec leaves the
    resolution automatic, the cells the program will use for a draft
    (cloth_spec.cpp resolved_resolution: max(64, cells_per_thread x threads))."""
    out = dict(fields)
    for family in ("warp", "weft"):
        for key in ("spacing_mm", "width_mm"):
            values = draft.get(f"{family}_{key}")
            if values:
                out[f"{family}_{key}"] = sum(values) / len(values)
    res = spec.get("resolution") if isinstance(spec.get("resolution"), dict) else {}
    per_thread = res.get("cells_per_thread", CELLS_PER_THREAD)
    for name, threads in (("cells_x", draft["ends"]), ("cells_y", draft["picks"])):
        if not res.get(name):
            out[name] = max(64, per_thread * threads)
    return out


def varies(values, rel=1e-6):
    """Whether per-thread values differ (the panel says its field is a mean)."""
    return bool(values) and max(values) - min(values) > rel * max(abs(v) for v in values)


def _same(name, a, b):
    if name in COLOR_FIELDS:
        return all(short_float(x) == short_float(y) for x, y in zip(a, b))
    if name in INT_FIELDS:
        return int(a) == int(b)
    return short_float(a) == short_float(b)


def changed_fields(fields, loaded):
    """{name: value} of the fields that differ from those loaded (the
    fields as the panel holds them, both read back from the properties)."""
    return {name: fields[name] for name in FIELDS
            if name in fields and name in loaded and not _same(name, fields[name], loaded[name])}


def inline_spec(base, wif_path, changed, warp_colors=None, weft_colors=None):
    """The cloth export writes for an edited WIF cloth: `base` (the spec the
    object came from: {} for a .wif, else the JSON spec with its overrides)
    with weave.wif made the absolute `wif_path`, every changed field written
    over it, and, when given, the per-thread colours as warp.colors /
    weft.colors (one per end / pick; they replace any warp.color)."""
    spec = copy.deepcopy(base) if isinstance(base, dict) else {}
    spec["weave"] = {"wif": os.path.abspath(wif_path)}
    for name, value in changed.items():
        keys = FIELDS[name][0]
        node = spec
        for key in keys[:-1]:
            if not isinstance(node.get(key), dict):
                node[key] = {}
            node = node[key]
        if name in COLOR_FIELDS:
            value = [short_float(c) for c in value]
        elif name in INT_FIELDS:
            value = int(value)
        else:
            value = short_float(value)
        node[keys[-1]] = value
    for family, colors in (("warp", warp_colors), ("weft", weft_colors)):
        if colors is None:
            continue
        yarn = spec.get(family) if isinstance(spec.get(family), dict) else {}
        yarn.pop("color", None)
        yarn["colors"] = [[short_float(x) for x in c] for c in colors]
        spec[family] = yarn
    return spec
