"""Reading a cloth material folder's manifest.json (docs/formats/material.md),
checked as far as Blender needs it, beside the lookup's reader
(core/lookup_manifest.py). The ranges are the program's (core/defaults.py).
Versions 1 to 3: version 1 is read as parts "rgb"; version 2's colour-free
parts ("specular-warp-weft") bring the cloth's threads and its colours;
version 3 (address "crossings") stores one block per class of crossings and
a per-crossing index (crossings.exr) instead of the whole repeat."""
import json
import math
import os
from dataclasses import dataclass

from .defaults import MATERIAL_DIRECTIONS_RANGE, MATERIAL_TEXELS_RANGE
from .errors import ClothbakeError

FORMAT = "clothbake-material"
HORIZON = "hemi-octahedral-horizon"
SQUARE = "hemi-octahedral"
RGB = "rgb"
SWF = "specular-warp-weft"   # colour-free parts: kNNNN.specular, .warp, .weft, .warp_next, .weft_next
VERSIONS = (1, 2, 3)
# Written only for a material addressed per crossing (--address crossings).
ADDRESSED_VERSION = 3
REPEAT, CROSSINGS = "repeat", "crossings"   # the manifest's `address`
FAMILIES = ("warp", "weft")
SWF_CHANNELS = ("specular", "warp", "weft", "warp_next", "weft_next")


@dataclass
class MaterialInfo:
    """What Blender reads of a material folder."""
    folder: str           # absolute path of the folder
    manifest: dict        # the manifest as read (the pack's cache key hashes it)
    texels: int           # S0, texels a side of one repeat at level 0 (a power of 2)
    levels: int           # mip levels, log2(texels) + 1
    k: int                # view nodes per side of each hemisphere's grid
    kl: int               # light nodes per side
    light_map: str        # SQUARE or HORIZON, the light grid's map
    max_rank: int         # SVD components stored per view node
    ranks: list           # per view node, the components it uses
    repeat_mm: list       # one weave repeat's size in mm (x, y, depth)
    depth_scale: float    # texture mm per world unit along the normal over along the surface
    name: str             # the cloth's name ("" if none)
    cloth_hash: str       # the cloth spec's hash ("" if none)
    parts: str = RGB      # RGB, or SWF (colour-free: the colours are given at render time)
    # SWF only, per family ("warp", "weft"):
    centres_mm: dict = None   # each thread's centre over one repeat, mm (x: warp, y: weft)
    colors: dict = None       # the baked-with colours: {"color": [r, g, b], "colors": [...]}
    parallax_depth_mm: float = 0.0  # --view-parallax's depth (view_parallax.h); 0: none
    # SWF only: repeats of the material in one repeat of the baked cloth's
    # draft as written (x, y), what an object's repeats_per_uv counts: a WIF
    # written over its colour repeat is baked over its weave's (107 x 107 for
    # a plain weave written over 214 ends and picks).
    written_repeats: tuple = (1.0, 1.0)
    # CROSSINGS only: the colour-free repeat's ends and picks, the blocks
    # (classes) and the index file (docs/formats/material.md, "Addressed per
    # crossing"); texels then counts a crossing's side, not the repeat's.
    address: str = REPEAT
    ends: int = 1
    picks: int = 1
    blocks: int = 1
    crossings_file: str = ""
    # CROSSINGS only, per family (warp, weft): whether its threads are
    # evenly spaced (the nodes place a point among them by arithmetic) or not
    # (through the pack's span image).
    even: tuple = (True, True)

    @property
    def block_grid(self):
        """(bx, by): a view node's tile holds the blocks bx across and by
        up (core/material_pack.py); (1, 1) for a whole repeat."""
        bx = math.isqrt(self.blocks - 1) + 1 if self.blocks > 1 else 1
        return bx, -(-self.blocks // bx)

    @property
    def threads_per_repeat(self):
        """(x, y): level-0 texels per repeat over `texels`: 1 for a whole
        repeat, the ends and picks for a material addressed per crossing."""
        return (self.ends, self.picks) if self.address == CROSSINGS else (1, 1)

    @property
    def channels(self):
        """The channel suffixes of a coefficient component."""
        return SWF_CHANNELS if self.parts == SWF else ("R", "G", "B")


def _field(m, key, kind, path):
    if key not in m:
        raise ClothbakeError("is missing", path, key)
    value = m[key]
    if kind is int and not (isinstance(value, int) and not isinstance(value, bool)):
        raise ClothbakeError("must be an integer", path, key)
    if kind is float and not isinstance(value, (int, float)):
        raise ClothbakeError("must be a number", path, key)
    if kind is str and not isinstance(value, str):
        raise ClothbakeError("must be a string", path, key)
    return value


def is_material_folder(folder):
    path = os.path.join(folder, "manifest.json")
    try:
        with open(path) as f:
            return json.load(f).get("format") == FORMAT
    except (OSError, ValueError, AttributeError):
        return False


def _load_json(folder, path):
    if not os.path.isdir(folder):
        raise ClothbakeError("is not a folder (a material folder holds manifest.json)", folder)
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise ClothbakeError(f"cannot read it: {e.strerror}", path) from None
    except ValueError as e:
        raise ClothbakeError(f"is not valid JSON: {e}", path) from None


def _check_files(files, levels, folder, path):
    """`files` names one image per level and the light factors, all in the folder."""
    if not isinstance(files, dict) or not isinstance(files.get("levels"), list) or \
            len(files["levels"]) != levels or not isinstance(files.get("light_factors"), str):
        raise ClothbakeError("must name one file per level and the light factors", path, "files")
    for name in files["levels"] + [files["light_factors"]]:
        if not isinstance(name, str) or os.path.basename(name) != name or \
                not os.path.isfile(os.path.join(folder, name)):
            raise ClothbakeError(f"names {name!r}, which is not in the folder", path, "files")


def read_material(folder):
    """The manifest of a material folder, checked as far as Blender needs it."""
    folder = os.path.abspath(folder)
    path = os.path.join(folder, "manifest.json")
    m = _load_json(folder, path)
    if not isinstance(m, dict) or m.get("format") != FORMAT:
        raise ClothbakeError(f"must be \"{FORMAT}\" (is this a material folder?)", path, "format")
    version = _field(m, "version", int, path)
    if version not in VERSIONS:
        raise ClothbakeError(f"must be {' or '.join(map(str, VERSIONS))} (a newer program wrote "
                             "this material? update the add-on)", path, "version")
    parts = RGB if version == 1 else m.get("parts", RGB)
    if parts not in (RGB, SWF):
        raise ClothbakeError(f"must be \"{RGB}\" or \"{SWF}\"", path, "parts")
    texels = _field(m, "texels", int, path)
    lo, hi = MATERIAL_TEXELS_RANGE
    if texels < lo or texels > hi or texels & (texels - 1):
        raise ClothbakeError(f"must be a power of 2 in {lo}..{hi}", path, "texels")
    levels = _field(m, "levels", int, path)
    if levels != int(round(math.log2(texels))) + 1:
        raise ClothbakeError("must be log2(texels) + 1", path, "levels")
    k = _field(m, "directions", int, path)
    kl = _field(m, "light_directions", int, path)
    for key, value in (("directions", k), ("light_directions", kl)):
        lo, hi = MATERIAL_DIRECTIONS_RANGE
        if not lo <= value <= hi:
            raise ClothbakeError(f"must be in {lo}..{hi}", path, key)
    if m.get("direction_map") != SQUARE:
        raise ClothbakeError(f"must be \"{SQUARE}\"", path, "direction_map")
    light_map = _field(m, "light_direction_map", str, path)
    if light_map not in (HORIZON, SQUARE):
        raise ClothbakeError(f"must be \"{HORIZON}\" or \"{SQUARE}\"", path, "light_direction_map")
    max_rank = _field(m, "max_rank", int, path)
    ranks = m.get("ranks")
    if not isinstance(ranks, list) or len(ranks) != 2 * k * k or \
            not all(isinstance(r, int) and 0 <= r <= max_rank for r in ranks):
        raise ClothbakeError(f"must be {2 * k * k} integers in 0..max_rank", path, "ranks")
    repeat = m.get("repeat_mm")
    if not isinstance(repeat, list) or len(repeat) != 3 or \
            not all(isinstance(x, (int, float)) and x > 0 for x in repeat):
        raise ClothbakeError("must be 3 positive numbers", path, "repeat_mm")
    # --view-parallax: the depth at which each view node is read shifted
    # (baker/core/material/view_parallax.h); 0 or absent: no shift.
    parallax = m.get("parallax_depth_mm", 0.0)
    if not isinstance(parallax, (int, float)) or isinstance(parallax, bool) or \
            not 0 <= parallax <= float(repeat[2]):
        raise ClothbakeError(f"must be a number in [0, {float(repeat[2]):g}] (the cloth's "
                             "thickness, mm)", path, "parallax_depth_mm")
    optics = m.get("optics")
    if not isinstance(optics, dict) or not isinstance(optics.get("depth_scale"), (int, float)):
        raise ClothbakeError("must hold depth_scale", path, "optics")
    _check_files(m.get("files"), levels, folder, path)
    cloth = m.get("cloth") if isinstance(m.get("cloth"), dict) else {}
    repeat = [float(x) for x in repeat]
    centres = colors = None
    written = (1.0, 1.0)
    if parts == SWF:
        centres = _thread_centres(cloth, repeat, path)
        colors = _baked_colours(cloth, path)
        written = _written_repeats(cloth, path)
    info = MaterialInfo(folder, m, texels, levels, k, kl, light_map, max_rank, ranks,
                        repeat, float(optics["depth_scale"]),
                        str(cloth.get("name", "")), str(cloth.get("hash", "")), parts,
                        centres, colors, float(parallax), written)
    address = m.get("address", REPEAT) if version == ADDRESSED_VERSION else REPEAT
    if address not in (REPEAT, CROSSINGS):
        raise ClothbakeError(f"must be \"{REPEAT}\" or \"{CROSSINGS}\"", path, "address")
    if address == CROSSINGS:
        _read_crossings(info, m, folder, path)
    return info


def _read_crossings(info, m, folder, path):
    """A material addressed per crossing: its counts and index file, and
    whether each family's threads are evenly spaced."""
    if info.parts != SWF:
        raise ClothbakeError(f"must be \"{SWF}\" for a material addressed per crossing",
                             path, "parts")
    c = m.get("crossings")
    if not isinstance(c, dict):
        raise ClothbakeError("must hold ends, picks, blocks and file", path, "crossings")
    counts = []
    for key in ("ends", "picks", "blocks"):
        value = c.get(key)
        if not isinstance(value, int) or isinstance(value, bool) or value < 1:
            raise ClothbakeError("must be a positive integer", path, f"crossings.{key}")
        counts.append(value)
    name = c.get("file")
    if not isinstance(name, str) or os.path.basename(name) != name or \
            not os.path.isfile(os.path.join(folder, name)):
        raise ClothbakeError(f"names {name!r}, which is not in the folder", path, "crossings.file")
    info.address = CROSSINGS
    info.ends, info.picks, info.blocks = counts
    info.crossings_file = os.path.join(folder, name)
    even = []
    for axis, (family, count, n) in enumerate(zip(FAMILIES, ("ends", "picks"), counts[:2])):
        centres = info.centres_mm[family]
        if len(centres) != n:
            raise ClothbakeError(f"holds {len(centres)} threads; crossings.{count} says {n}",
                                 path, f"cloth.threads.{family}.centres_mm")
        pitch = info.repeat_mm[axis] / n
        even.append(all(abs((b - a) - pitch) <= 1e-3 * pitch
                        for a, b in zip(centres, centres[1:] + [centres[0] + info.repeat_mm[axis]])))
    info.even = tuple(even)


def _written_repeats(cloth, path):
    """cloth.written_repeats: two whole numbers >= 1 (absent: 1, 1)."""
    w = cloth.get("written_repeats", [1, 1])
    if not isinstance(w, list) or len(w) != 2 or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and x >= 1 and
            float(x).is_integer() for x in w):
        raise ClothbakeError("must be two whole numbers of at least 1", path,
                             "cloth.written_repeats")
    return (float(w[0]), float(w[1]))


def _rgb(value):
    return isinstance(value, list) and len(value) == 3 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) for c in value)


def _thread_centres(cloth, repeat, path):
    """cloth.threads: per family, the threads' centres, ascending in
    [0, repeat) (x for the warp, y for the weft)."""
    threads = cloth.get("threads")
    out = {}
    for axis, family in enumerate(FAMILIES):
        field = f"cloth.threads.{family}.centres_mm"
        entry = threads.get(family) if isinstance(threads, dict) else None
        c = entry.get("centres_mm") if isinstance(entry, dict) else None
        if not isinstance(c, list) or not c or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in c):
            raise ClothbakeError("must be a non-empty array of numbers (a colour-free "
                                 "material's thread centres)", path, field)
        if any(not 0 <= x < repeat[axis] * (1 + 1e-6) for x in c) or \
                any(b <= a for a, b in zip(c, c[1:])):
            raise ClothbakeError(f"must ascend within the repeat (0..{repeat[axis]:g} mm)",
                                 path, field)
        out[family] = [float(x) for x in c]
    return out


def _baked_colours(cloth, path):
    """cloth.colors: per family its colour and per-thread colours (linear)."""
    given = cloth.get("colors")
    out = {}
    for family in FAMILIES:
        entry = given.get(family) if isinstance(given, dict) else None
        if not isinstance(entry, dict) or not _rgb(entry.get("color")):
            raise ClothbakeError("must be an array of 3 numbers", path,
                                 f"cloth.colors.{family}.color")
        seq = entry.get("colors", [])
        if not isinstance(seq, list) or not all(_rgb(c) for c in seq):
            raise ClothbakeError("must be an array of colours (3 numbers each)", path,
                                 f"cloth.colors.{family}.colors")
        out[family] = {"color": [float(x) for x in entry["color"]],
                       "colors": [[float(x) for x in c] for c in seq]}
    return out


