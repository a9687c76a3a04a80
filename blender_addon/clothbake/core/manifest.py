"""Reading a lookup folder's manifest.json (docs/lookup-format.md, version 1).

Checks what clothbake's own reader checks (baker/io/lookup_io.cpp), so a
broken or foreign lookup is refused with the file and field named, before
Blender loads a single image.
"""
import json
import os
import re
from dataclasses import dataclass, field

from .directions import HEMI_OCTAHEDRAL, POLAR
from .errors import ClothbakeError

FORMAT = "clothbake-lookup"
VERSION = 1
_MAPS = {HEMI_OCTAHEDRAL: "corners", POLAR: "polar"}


@dataclass
class LookupObject:
    """One cloth object of a lookup: its atlas layout and files."""
    index: int
    name: str
    cloth_hash: str
    quads: int
    tile_width: int
    tile_height: int
    gutter: int
    rects: list          # per quad: (x, y, size), size 0 = no square
    baked: list          # per quad: string of 2 K^2 '0'/'1'
    files: dict          # "front"/"back" -> absolute path or None

    def quad_baked(self, quad):
        return "1" in self.baked[quad]

    def atlas_size(self, k):
        """(width, height) in pixels of each side's atlas."""
        return k * self.tile_width, k * self.tile_height


@dataclass
class Lookup:
    folder: str
    scene_hash: str
    direction_map: str
    k: int
    settings: dict
    lights: list
    objects: list = field(default_factory=list)
    statistics: dict = field(default_factory=dict)

    def object_named(self, name):
        for o in self.objects:
            if o.name == name:
                return o
        return None


def _require(obj, key, kinds, path, where):
    if not isinstance(obj, dict) or key not in obj:
        raise ClothbakeError("missing key", path, f"{where}{key}")
    value = obj[key]
    # bool is an int in Python; a flag is never a number here.
    if isinstance(value, bool) and bool not in kinds or not isinstance(value, kinds):
        names = " or ".join(k.__name__ for k in kinds)
        raise ClothbakeError(f"must be {names}, got {type(value).__name__}", path, f"{where}{key}")
    return value


def _int(obj, key, path, where, lo, hi=None):
    value = _require(obj, key, (int,), path, where)
    if value < lo or (hi is not None and value > hi):
        bound = f"[{lo}, {hi}]" if hi is not None else f">= {lo}"
        raise ClothbakeError(f"must be in {bound}, got {value}", path, f"{where}{key}")
    return value


def read_manifest(folder):
    """Reads and checks FOLDER/manifest.json; returns a Lookup.
    Raises ClothbakeError naming the file and field."""
    folder = os.path.abspath(folder)
    path = os.path.join(folder, "manifest.json")
    if not os.path.isdir(folder):
        raise ClothbakeError("no such lookup folder", folder)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise ClothbakeError(f"cannot read the manifest: {e.strerror}", path) from None
    try:
        root = json.loads(text)
    except json.JSONDecodeError as e:
        raise ClothbakeError(f"invalid JSON: {e.msg}", path, f"line {e.lineno}") from None
    if not isinstance(root, dict):
        raise ClothbakeError("must be a JSON object", path)

    fmt = _require(root, "format", (str,), path, "")
    if fmt != FORMAT:
        raise ClothbakeError(f"not a clothbake lookup (format '{fmt}', expected '{FORMAT}')",
                             path, "format")
    version = _require(root, "version", (int,), path, "")
    if version != VERSION:
        raise ClothbakeError(f"this lookup has format version {version}; this add-on reads "
                             f"version {VERSION}", path, "version")
    scene_hash = _require(root, "scene_hash", (str,), path, "")
    if not re.fullmatch(r"[0-9a-f]{16}", scene_hash):
        raise ClothbakeError("must be 16 lowercase hex digits", path, "scene_hash")

    dmap = _require(root, "direction_map", (dict,), path, "")
    kind = _require(dmap, "type", (str,), path, "direction_map.")
    if kind not in _MAPS:
        raise ClothbakeError(f"unknown direction map '{kind}' (known: {', '.join(_MAPS)})",
                             path, "direction_map.type")
    nodes = _require(dmap, "nodes", (str,), path, "direction_map.")
    if nodes != _MAPS[kind]:
        raise ClothbakeError(f"must be '{_MAPS[kind]}' for a {kind} map, got '{nodes}'",
                             path, "direction_map.nodes")
    k = _int(dmap, "k", path, "direction_map.", 2, 64)

    settings = root.get("settings", {})
    lights = root.get("lights", [])
    statistics = root.get("statistics", {})
    objects_json = _require(root, "objects", (list,), path, "")
    lookup = Lookup(folder, scene_hash, kind, k,
                    settings if isinstance(settings, dict) else {},
                    lights if isinstance(lights, list) else [],
                    statistics=statistics if isinstance(statistics, dict) else {})
    flag_re = re.compile(r"[01]{%d}" % (2 * k * k))
    for o, oj in enumerate(objects_json):
        where = f"objects[{o}]."
        if not isinstance(oj, dict):
            raise ClothbakeError("must be an object", path, f"objects[{o}]")
        name = oj.get("name", "")
        quads = _int(oj, "quads", path, where, 0)
        tile = _require(oj, "tile", (list,), path, where)
        if len(tile) != 2 or not all(isinstance(v, int) and not isinstance(v, bool) and v >= 1
                                     for v in tile):
            raise ClothbakeError("must be [w, h], integers >= 1", path, where + "tile")
        gutter = _int(oj, "gutter", path, where, 0)
        rects_json = _require(oj, "rects", (list,), path, where)
        baked_json = _require(oj, "baked", (list,), path, where)
        if len(rects_json) != quads:
            raise ClothbakeError(f"has {len(rects_json)} entries, expected one per quad ({quads})",
                                 path, where + "rects")
        if len(baked_json) != quads:
            raise ClothbakeError(f"has {len(baked_json)} entries, expected one per quad ({quads})",
                                 path, where + "baked")
        rects = []
        for q, r in enumerate(rects_json):
            field_name = f"{where}rects[{q}]"
            if (not isinstance(r, list) or len(r) != 3 or
                    not all(isinstance(v, int) and not isinstance(v, bool) for v in r)):
                raise ClothbakeError("must be [x, y, size], integers", path, field_name)
            x, y, size = r
            if size < 0 or (size > 0 and (x < 0 or y < 0 or x + size > tile[0] or
                                          y + size > tile[1])):
                raise ClothbakeError(f"square [{x}, {y}, {size}] lies outside the "
                                     f"{tile[0]} x {tile[1]} tile", path, field_name)
            rects.append((x, y, size))
        for q, flags in enumerate(baked_json):
            if not isinstance(flags, str) or not flag_re.fullmatch(flags):
                raise ClothbakeError(f"must be a string of {2 * k * k} characters '0' or '1'",
                                     path, f"{where}baked[{q}]")
        files_json = _require(oj, "files", (dict,), path, where)
        files = {}
        for side, key in enumerate(("front", "back")):
            value = files_json.get(key)
            side_baked = any("1" in flags[side * k * k:(side + 1) * k * k] for flags in baked_json)
            if value is None:
                if side_baked:
                    raise ClothbakeError(f"the {key} side has baked nodes but no file",
                                         path, f"{where}files.{key}")
                files[key] = None
                continue
            if not isinstance(value, str) or not value or os.path.basename(value) != value:
                raise ClothbakeError("must be a file name in the lookup folder",
                                     path, f"{where}files.{key}")
            file_path = os.path.join(folder, value)
            if not os.path.isfile(file_path):
                raise ClothbakeError("the lookup image is missing", file_path)
            files[key] = file_path
        lookup.objects.append(LookupObject(o, name if isinstance(name, str) else "",
                                           str(oj.get("cloth_hash", "")), quads, tile[0], tile[1],
                                           gutter, rects, list(baked_json), files))
    if not lookup.objects:
        raise ClothbakeError("has no objects", path, "objects")
    return lookup
