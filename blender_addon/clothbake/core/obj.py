"""Wavefront OBJ of quads with UVs, read and written the way clothbake's
reader (baker/io/obj_reader.cpp, docs/formats/scene.md "Meshes") does, so
face q in Blender is quad q of the lookup.

The Blender add-on reads OBJ itself rather than through Blender's importer
because the lookup is addressed by face order and corner order, which an
importer is free to change (and Blender's splits vertices by UV seams).
"""
import math
from dataclasses import dataclass, field

from .errors import ClothbakeError

_IGNORED = {"vn", "o", "g", "s", "usemtl", "mtllib"}


@dataclass
class QuadMeshData:
    positions: list = field(default_factory=list)  # [(x, y, z)]
    uvs: list = field(default_factory=list)        # [(u, v)]
    # per quad: ((p0, p1, p2, p3), (t0, t1, t2, t3)), 0-based indices
    quads: list = field(default_factory=list)


def _number(path, line, token, what):
    try:
        value = float(token)
    except ValueError:
        raise ClothbakeError(f"malformed number '{token}' in {what}", path,
                             f"line {line}") from None
    if not math.isfinite(value) or abs(value) > 3.0e38:
        raise ClothbakeError(f"non-finite number '{token}' in {what}", path, f"line {line}")
    return value


def _index(path, line, token, corner, count):
    try:
        i = int(token)
    except ValueError:
        i = 0
    if i == 0:
        raise ClothbakeError(f"malformed index '{token}' in face corner '{corner}' "
                             "(OBJ indices are non-zero integers)", path, f"line {line}")
    return i - 1 if i > 0 else count + i


def read_obj(path):
    """Reads a quad OBJ; raises ClothbakeError naming the file and line."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise ClothbakeError(f"cannot read the mesh: {e.strerror}", path) from None
    mesh = QuadMeshData()
    pending = []  # (line, [(p, t)]) resolved after all elements are known
    for number, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        tokens = text.split()
        key = tokens[0]
        if key == "v":
            if len(tokens) < 4:
                raise ClothbakeError("vertex needs 3 coordinates", path, f"line {number}")
            mesh.positions.append(tuple(_number(path, number, t, "vertex") for t in tokens[1:4]))
        elif key == "vt":
            if len(tokens) < 3:
                raise ClothbakeError("texture vertex needs 2 coordinates", path, f"line {number}")
            mesh.uvs.append(tuple(_number(path, number, t, "texture vertex") for t in tokens[1:3]))
        elif key == "f":
            corners = tokens[1:]
            if len(corners) != 4:
                raise ClothbakeError(f"face has {len(corners)} corners; clothbake needs quads "
                                     "(4 corners)", path, f"line {number}")
            refs = []
            for c in corners:
                parts = c.split("/")
                if len(parts) < 2 or not parts[1]:
                    raise ClothbakeError(f"face corner '{c}' has no UV index (p/t or p/t/n "
                                         "needed)", path, f"line {number}")
                refs.append((_index(path, number, parts[0], c, len(mesh.positions)),
                             _index(path, number, parts[1], c, len(mesh.uvs))))
            pending.append((number, refs))
        elif key in _IGNORED:
            continue
        else:
            raise ClothbakeError(f"unsupported statement '{key}'", path, f"line {number}")
    for number, refs in pending:
        for p, t in refs:
            if not 0 <= p < len(mesh.positions):
                raise ClothbakeError(f"vertex index {p + 1} out of range (1..{len(mesh.positions)})",
                                     path, f"line {number}")
            if not 0 <= t < len(mesh.uvs):
                raise ClothbakeError(f"UV index {t + 1} out of range (1..{len(mesh.uvs)})",
                                     path, f"line {number}")
        mesh.quads.append((tuple(p for p, _ in refs), tuple(t for _, t in refs)))
    if not mesh.quads:
        raise ClothbakeError("mesh has no faces", path)
    return mesh


def format_obj(mesh, comment="written by the clothbake Blender add-on"):
    """OBJ text of a QuadMeshData (exact round trip of float32 values)."""
    out = [f"# {comment}"]
    out += ["v %.9g %.9g %.9g" % p for p in mesh.positions]
    out += ["vt %.9g %.9g" % t for t in mesh.uvs]
    for ps, ts in mesh.quads:
        out.append("f " + " ".join(f"{p + 1}/{t + 1}" for p, t in zip(ps, ts)))
    return "\n".join(out) + "\n"
