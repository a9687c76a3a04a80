"""The add-on's manifest reader: a real bake reads; each broken manifest is
refused with the file and field named (the same checks as clothbake's own
reader, docs/formats/lookup.md "Checks a reader makes")."""
import json
import os
import shutil
import subprocess

import pytest

from clothbake.core.errors import ClothbakeError
from clothbake.core.lookup_manifest import read_manifest


@pytest.fixture(scope="module")
def slab_bake(tmp_path_factory, request):
    source = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    binary = os.environ.get("CLOTHBAKE_BIN", os.path.join(source, "build", "baker", "clothbake"))
    out = tmp_path_factory.mktemp("bake") / "slab"
    subprocess.run([binary, "bake", os.path.join(source, "testscenes", "slab", "scene.json"),
                    "-o", str(out), "--directions", "3", "--texels", "4", "--spp", "1", "--quiet"],
                   check=True, stdout=subprocess.DEVNULL)
    return out


def test_reads_a_real_bake(slab_bake):
    lookup = read_manifest(slab_bake)
    assert lookup.k == 3 and lookup.direction_map == "hemi-octahedral"
    (obj,) = lookup.objects
    assert obj.quads == 1 and obj.sizes == [4]
    assert obj.baked[0] == "1" * 18
    front, back = obj.sides["front"], obj.sides["back"]
    assert os.path.isfile(front.path) and os.path.isfile(back.path)
    # A full bake: all 9 nodes of each side have a square.
    assert sorted(front.squares) == [(0, n) for n in range(9)]
    assert sorted(back.squares) == [(0, n) for n in range(9, 18)]


def broken(slab_bake, tmp_path, edit):
    folder = tmp_path / "broken"
    shutil.copytree(slab_bake, folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    edit(manifest, folder)
    (folder / "manifest.json").write_text(json.dumps(manifest))
    return folder


CASES = [
    ("format", lambda m, f: m.update(format="other"), "format: not a clothbake lookup"),
    ("version", lambda m, f: m.update(version=1),
     "version: this lookup has format version 1; this add-on reads version 2"),
    ("k", lambda m, f: m["direction_map"].update(k=65), "direction_map.k: must be in [2, 64], got 65"),
    ("map", lambda m, f: m["direction_map"].update(type="cube"),
     "direction_map.type: unknown direction map 'cube'"),
    ("sizes", lambda m, f: m["objects"][0]["sizes"].append(4),
     "objects[0].sizes: must be 1 integers in [0, 65536] (one per quad)"),
    ("square outside", lambda m, f: m["objects"][0]["sides"]["front"]["squares"][0].__setitem__(2, 1000),
     "objects[0].sides.front.squares[0]: the square and its gutter do not fit in the"),
    ("square node", lambda m, f: m["objects"][0]["sides"]["back"]["squares"][0].__setitem__(1, 0),
     "objects[0].sides.back.squares[0]: node 0 is not a node of the back side"),
    ("flags", lambda m, f: m["objects"][0]["baked"].__setitem__(0, "10"),
     "objects[0].baked[0]: must be a string of 18 characters '0' or '1'"),
    ("sizes type", lambda m, f: m["objects"][0].update(sizes="big"),
     "objects[0].sizes: must be list"),
    ("no side", lambda m, f: m["objects"][0]["sides"].update(front=None),
     "objects[0].baked[0]: node 0 is marked baked but has no square in objects[0].sides.front"),
    ("path in name", lambda m, f: m["objects"][0]["sides"]["front"].update(file="../x.exr"),
     "objects[0].sides.front.file: must be a file name in the lookup folder"),
    ("missing image", lambda m, f: os.remove(f / m["objects"][0]["sides"]["back"]["file"]),
     "the lookup image is missing"),
    ("hash", lambda m, f: m.update(scene_hash="XYZ"), "scene_hash: must be 16 lowercase hex digits"),
    ("missing key", lambda m, f: m.pop("objects"), "objects: missing key"),
    ("truncated image", lambda m, f: (f / m["objects"][0]["sides"]["back"]["file"]).write_bytes(
        (f / m["objects"][0]["sides"]["back"]["file"]).read_bytes()[:-1]),
     "the lookup image is damaged or truncated"),
    ("mesh area", lambda m, f: m["objects"][0]["mesh"].pop("area"), "objects[0].mesh.area: missing"),
    ("mesh bounds", lambda m, f: m["objects"][0]["mesh"].update(uv_min=[0]),
     "objects[0].mesh.uv_min: must be 2 finite numbers"),
    ("image size", lambda m, f: m["objects"][0]["sides"]["front"].update(
        size=[m["objects"][0]["sides"]["front"]["size"][0] + 1,
              m["objects"][0]["sides"]["front"]["size"][1]]),
     "pixels; the manifest says"),
]


@pytest.mark.parametrize("name,edit,message", CASES, ids=[c[0] for c in CASES])
def test_refuses_broken_manifests(slab_bake, tmp_path, name, edit, message):
    folder = broken(slab_bake, tmp_path, edit)
    with pytest.raises(ClothbakeError) as err:
        read_manifest(folder)
    assert message in str(err.value)
    assert str(folder) in str(err.value)


def test_refuses_invalid_json_and_missing_folder(tmp_path):
    (tmp_path / "manifest.json").write_text("{\"format\": ")
    with pytest.raises(ClothbakeError, match=r"manifest.json: line 1: invalid JSON"):
        read_manifest(tmp_path)
    with pytest.raises(ClothbakeError, match="no such lookup folder"):
        read_manifest(tmp_path / "nope")


def test_refuses_a_folder_without_manifest_and_binary_text(tmp_path):
    with pytest.raises(ClothbakeError) as err:
        read_manifest(tmp_path)
    assert str(err.value) == f"{tmp_path}: no manifest.json in this folder; it is not a " \
                             "clothbake lookup (bake into it first)"
    (tmp_path / "manifest.json").write_bytes(b"\xff\xfe{")
    with pytest.raises(ClothbakeError, match=r"manifest.json: not UTF-8 text \(byte 0\)"):
        read_manifest(tmp_path)
