"""Reading a cloth material folder's manifest.json (docs/material-format.md),
checked as far as Blender needs it, beside the lookup's reader
(core/manifest.py). The ranges are the program's (core/defaults.py)."""
import json
import math
import os
from dataclasses import dataclass

from .defaults import MATERIAL_DIRECTIONS_RANGE, MATERIAL_TEXELS_RANGE
from .errors import ClothbakeError

FORMAT = "clothbake-material"
HORIZON = "hemi-octahedral-horizon"
SQUARE = "hemi-octahedral"


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
    if version not in (1, 2):
        raise ClothbakeError("must be 1 or 2", path, "version")
    # Version 2 adds colour-free parts (docs/material-format.md); the add-on
    # applies RGB materials only, and Bake material asks for them.
    parts = m.get("parts", "rgb") if version == 2 else "rgb"
    if parts != "rgb":
        raise ClothbakeError(f"is \"{parts}\": colour-free materials are not applied in "
                             "Blender yet; bake this one with `clothbake material ... --parts "
                             "rgb` (Bake material in the panel does)", path, "parts")
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
    optics = m.get("optics")
    if not isinstance(optics, dict) or not isinstance(optics.get("depth_scale"), (int, float)):
        raise ClothbakeError("must hold depth_scale", path, "optics")
    _check_files(m.get("files"), levels, folder, path)
    cloth = m.get("cloth") if isinstance(m.get("cloth"), dict) else {}
    return MaterialInfo(folder, m, texels, levels, k, kl, light_map, max_rank, ranks,
                        [float(x) for x in repeat], float(optics["depth_scale"]),
                        str(cloth.get("name", "")), str(cloth.get("hash", "")))


