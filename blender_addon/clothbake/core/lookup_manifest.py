"""Reading a lookup folder's manifest.json (docs/formats/lookup.md, version 2).

Checks what clothbake's own reader checks (baker/io/lookup_manifest.cpp), so a
broken or foreign lookup is refused with the file and field named, before
Blender loads a single image.
"""
import json
import os
import re
from dataclasses import dataclass, field

from .directions import HEMI_OCTAHEDRAL, POLAR
from .errors import ClothbakeError
from .exr import check_exr
from . import defaults, lookup_mesh_summary

FORMAT = "clothbake-lookup"
K_RANGE = defaults.DIRECTIONS_RANGE
VERSION = 2
_MAPS = {HEMI_OCTAHEDRAL: "corners", POLAR: "polar"}


@dataclass
class SideAtlas:
    """One side's packed atlas: its file, size and where each (quad, node)
    square's top-left texel (inside the gutter) is."""
    path: str
    width: int
    height: int
    squares: dict        # (quad, node) -> (x, y)


@dataclass
class LookupObject:
    """One cloth object of a lookup: per-quad square sizes, flags, atlases."""
    index: int
    name: str
    cloth_hash: str
    quads: int
    gutter: int
    sizes: list          # per quad: texels per side of its squares, 0 = none
    baked: list          # per quad: string of 2 K^2 '0'/'1'
    sides: dict          # "front"/"back" -> SideAtlas or None
    mesh: dict = None    # the baked mesh's summary (lookup_mesh_summary.py); None in older lookups

    def quad_baked(self, quad):
        return "1" in self.baked[quad]

    def is_baked(self, quad, node):
        return self.baked[quad][node] == "1"


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


def _load(folder):
    """(path, root object) of FOLDER/manifest.json."""
    path = os.path.join(folder, "manifest.json")
    if not os.path.isdir(folder):
        raise ClothbakeError("no such lookup folder", folder)
    if not os.path.lexists(path):
        raise ClothbakeError("no manifest.json in this folder; it is not a clothbake lookup "
                             "(bake into it first)", folder)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise ClothbakeError(f"cannot read the manifest: {e.strerror}", path) from None
    except UnicodeDecodeError as e:
        raise ClothbakeError(f"not UTF-8 text (byte {e.start}); a manifest is a JSON file",
                             path) from None
    try:
        root = json.loads(text)
    except json.JSONDecodeError as e:
        raise ClothbakeError(f"invalid JSON: {e.msg}", path, f"line {e.lineno}") from None
    if not isinstance(root, dict):
        raise ClothbakeError("must be a JSON object", path)
    return path, root


def _header(root, path):
    """(scene hash, direction map kind, K): the format, version and map checked."""
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
    return scene_hash, kind, _int(dmap, "k", path, "direction_map.", *K_RANGE)


def _squares(sj, side, key, quads, sizes, gutter, per_side, width, height, path, field_name):
    """{(quad, node): (x, y)} of one side's atlas, each square checked to fit."""
    squares = {}
    for i, sq in enumerate(_require(sj, "squares", (list,), path, field_name + ".")):
        sq_field = f"{field_name}.squares[{i}]"
        if (not isinstance(sq, list) or len(sq) != 4 or
                not all(isinstance(v, int) and not isinstance(v, bool) for v in sq)):
            raise ClothbakeError("must be [quad, node, x, y], integers", path, sq_field)
        q, n, x, y = sq
        if not 0 <= q < quads:
            raise ClothbakeError(f"quad {q} out of range", path, sq_field)
        if not side * per_side <= n < (side + 1) * per_side:
            raise ClothbakeError(f"node {n} is not a node of the {key} side", path,
                                 sq_field)
        w = sizes[q]
        if w == 0:
            raise ClothbakeError(f"quad {q} has size 0", path, sq_field)
        if x - gutter < 0 or y - gutter < 0 or x + w + gutter > width or \
                y + w + gutter > height:
            raise ClothbakeError(f"the square and its gutter do not fit in the {width} x "
                                 f"{height} atlas", path, sq_field)
        if (q, n) in squares:
            raise ClothbakeError("a second square for the same quad and node", path,
                                 sq_field)
        squares[q, n] = (x, y)
    return squares


def _side(sj, side, key, quads, sizes, gutter, per_side, folder, path, where):
    """One side's SideAtlas (None when not baked), its image checked whole."""
    field_name = f"{where}sides.{key}"
    if sj is None:
        return None
    if not isinstance(sj, dict):
        raise ClothbakeError("must be an object or null", path, field_name)
    size = _require(sj, "size", (list,), path, field_name + ".")
    if len(size) != 2 or not all(isinstance(v, int) and not isinstance(v, bool) and
                                 1 <= v <= 65536 for v in size):
        raise ClothbakeError("must be two integers in [1, 65536]", path,
                             field_name + ".size")
    width, height = size
    squares = _squares(sj, side, key, quads, sizes, gutter, per_side, width, height, path,
                       field_name)
    file_name = _require(sj, "file", (str,), path, field_name + ".")
    if not file_name or os.path.basename(file_name) != file_name or \
            file_name.startswith("."):
        raise ClothbakeError("must be a file name in the lookup folder", path,
                             field_name + ".file")
    file_path = os.path.join(folder, file_name)
    if not os.path.isfile(file_path):
        raise ClothbakeError("the lookup image is missing", file_path)
    shape = check_exr(file_path)  # Blender hangs on a truncated EXR
    if shape is not None and shape != (width, height):
        raise ClothbakeError(f"the image is {shape[0]} x {shape[1]} pixels; the manifest "
                             f"says {width} x {height}", file_path)
    return SideAtlas(file_path, width, height, squares)


def _object(oj, o, k, folder, path):
    """objects[o] as a LookupObject."""
    where = f"objects[{o}]."
    if not isinstance(oj, dict):
        raise ClothbakeError("must be an object", path, f"objects[{o}]")
    name = oj.get("name", "")
    quads = _int(oj, "quads", path, where, 0)
    gutter = _int(oj, "gutter", path, where, 0, 64)
    sizes = _require(oj, "sizes", (list,), path, where)
    if len(sizes) != quads or not all(isinstance(v, int) and not isinstance(v, bool) and
                                      0 <= v <= 65536 for v in sizes):
        raise ClothbakeError(f"must be {quads} integers in [0, 65536] (one per quad)", path,
                             where + "sizes")
    baked_json = _require(oj, "baked", (list,), path, where)
    if len(baked_json) != quads:
        raise ClothbakeError(f"has {len(baked_json)} entries, expected one per quad ({quads})",
                             path, where + "baked")
    flag_re = re.compile(r"[01]{%d}" % (2 * k * k))
    for q, flags in enumerate(baked_json):
        if not isinstance(flags, str) or not flag_re.fullmatch(flags):
            raise ClothbakeError(f"must be a string of {2 * k * k} characters '0' or '1'",
                                 path, f"{where}baked[{q}]")
    sides_json = _require(oj, "sides", (dict,), path, where)
    per_side = k * k
    sides = {key: _side(sides_json.get(key), side, key, quads, sizes, gutter, per_side, folder,
                        path, where)
             for side, key in enumerate(("front", "back"))}
    for q, flags in enumerate(baked_json):
        for n, flag in enumerate(flags):
            side = sides["front" if n < per_side else "back"]
            if flag == "1" and (side is None or (q, n) not in side.squares):
                raise ClothbakeError(f"node {n} is marked baked but has no square in "
                                     f"{where}sides.{'front' if n < per_side else 'back'}"
                                     ".squares", path, f"{where}baked[{q}]")
    mesh = lookup_mesh_summary.parse(oj.get("mesh"), path, where + "mesh")
    return LookupObject(o, name if isinstance(name, str) else "",
                        str(oj.get("cloth_hash", "")), quads, gutter, sizes,
                        list(baked_json), sides, mesh)


def read_manifest(folder):
    """Reads and checks FOLDER/manifest.json; returns a Lookup.
    Raises ClothbakeError naming the file and field."""
    folder = os.path.abspath(folder)
    path, root = _load(folder)
    scene_hash, kind, k = _header(root, path)
    settings = root.get("settings", {})
    lights = root.get("lights", [])
    statistics = root.get("statistics", {})
    objects_json = _require(root, "objects", (list,), path, "")
    lookup = Lookup(folder, scene_hash, kind, k,
                    settings if isinstance(settings, dict) else {},
                    lights if isinstance(lights, list) else [],
                    statistics=statistics if isinstance(statistics, dict) else {})
    for o, oj in enumerate(objects_json):
        lookup.objects.append(_object(oj, o, k, folder, path))
    if not lookup.objects:
        raise ClothbakeError("has no objects", path, "objects")
    return lookup
