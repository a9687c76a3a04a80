"""clothbake.core.scene_export: the export is the inverse of the import's
camera and light conversions, writes files clothbake reads back, and
refuses what clothbake cannot take (non-quads) naming object and face.

    /usr/bin/python3 -m pytest tests/addon
"""
import json
import math
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))

from clothbake.core import scene_export as se  # noqa: E402
from clothbake.core.errors import ClothbakeError  # noqa: E402
from clothbake.core.obj import read_obj  # noqa: E402
from clothbake.core.scene import (blender_camera, blender_light, camera_basis,  # noqa: E402
                                  load_scene)

PAPER = os.path.join(ROOT, "testscenes", "paper", "scene.json")
SLAB = os.path.join(ROOT, "testscenes", "slab", "scene.json")


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def as_float32(matrix):
    """A matrix as Blender stores it."""
    return [[f32(v) for v in row] for row in matrix]


def assert_vec(a, b, tol):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert abs(x - y) <= tol, (a, b)


def export_camera(cam, hint=None, float32=False):
    b = blender_camera(cam)
    matrix = as_float32(b["matrix"]) if float32 else b["matrix"]
    lens = f32(b["lens"]) if float32 else b["lens"]
    return se.camera_from_blender(matrix, lens, b["sensor_width"], b["sensor_height"],
                                  b["sensor_fit"], b["resolution"], hint=hint)


@pytest.mark.parametrize("scene", [PAPER, SLAB])
def test_camera_round_trip_without_hint_is_the_same_camera(scene):
    cam = load_scene(scene)["camera"]
    out = export_camera(cam)
    assert_vec(out["position"], cam["position"], 1e-6)
    assert abs(out["fov_deg"] - cam["fov_deg"]) <= 1e-6
    assert out["fov_axis"] == cam["fov_axis"]
    assert out["resolution"] == cam["resolution"]
    for a, b in zip(camera_basis(out), camera_basis(cam)):
        assert_vec(a, b, 1e-6)
    # look_at lies straight ahead.
    forward = camera_basis(cam)[2]
    offset = [a - b for a, b in zip(out["look_at"], out["position"])]
    assert_vec([c / math.sqrt(sum(x * x for x in offset)) for c in offset], forward, 1e-9)
    assert se.same_camera(out, cam)


@pytest.mark.parametrize("scene", [PAPER, SLAB])
def test_camera_through_float32_with_hint_gives_the_original_numbers(scene):
    cam = load_scene(scene)["camera"]
    out = export_camera(cam, hint=cam, float32=True)
    assert out == cam


def test_moved_camera_keeps_hint_distance_but_not_its_numbers():
    cam = load_scene(PAPER)["camera"]
    b = blender_camera(cam)
    b["matrix"][0][3] += 0.5  # move along world x
    out = se.camera_from_blender(b["matrix"], b["lens"], 36, 36, "HORIZONTAL", [426, 266],
                                 hint=cam)
    assert_vec(out["position"], [cam["position"][0] + 0.5] + cam["position"][1:], 1e-6)
    dist = lambda c: math.dist(c["position"], c["look_at"])  # noqa: E731
    assert abs(dist(out) - dist(cam)) <= 1e-9
    assert not se.same_camera(out, cam)


def test_sensor_fit_auto_follows_the_larger_side():
    ident = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 5], [0, 0, 0, 1]]
    wide = se.camera_from_blender(ident, 50, 36, 24, "AUTO", [200, 100])
    tall = se.camera_from_blender(ident, 50, 36, 24, "AUTO", [100, 200])
    vert = se.camera_from_blender(ident, 50, 36, 24, "VERTICAL", [100, 200])
    assert wide["fov_axis"] == "horizontal" and tall["fov_axis"] == "vertical"
    assert abs(wide["fov_deg"] - math.degrees(2 * math.atan(18 / 50))) < 1e-12
    assert abs(tall["fov_deg"] - wide["fov_deg"]) < 1e-12  # AUTO uses sensor_width
    assert abs(vert["fov_deg"] - math.degrees(2 * math.atan(12 / 50))) < 1e-12
    assert_vec(wide["look_at"], [0, 0, 4], 1e-12)


@pytest.mark.parametrize("float32", [False, True])
def test_lights_round_trip(float32):
    lights = load_scene(PAPER)["lights"]
    for i, light in enumerate(lights):
        b = blender_light(light)
        matrix = as_float32(b["matrix"]) if float32 else b["matrix"]
        energy = f32(b["energy"]) if float32 else b["energy"]
        color = [f32(c) for c in b["color"]] if float32 else b["color"]
        plain = se.light_from_blender(f"l{i}", b["type"], matrix, color, energy)
        assert plain["type"] == light["type"]
        assert_vec(plain["color"], light["color"], 1e-6)
        assert abs(plain["intensity"] - light["intensity"]) <= 1e-6 * light["intensity"]
        if light["type"] == "directional":
            d = light["direction"]
            n = math.sqrt(sum(c * c for c in d))
            assert_vec(plain["direction"], [c / n for c in d], 1e-6)
        else:
            assert_vec(plain["position"], light["position"], 1e-6)
        hinted = se.light_from_blender(f"l{i}", b["type"], matrix, color, energy, hint=light)
        assert hinted == light


def test_unsupported_light_names_the_light():
    with pytest.raises(ClothbakeError, match="light 'lamp': area lights are not supported"):
        se.light_from_blender("lamp", "AREA", [[1, 0, 0, 0]] * 4, [1, 1, 1], 1)


def test_quad_mesh_keeps_face_and_corner_order_and_shares_uvs():
    paper = load_scene(PAPER)
    original = read_obj(paper["objects"][0]["mesh_path"])
    faces = [ps for ps, _ in original.quads]
    face_uvs = [[original.uvs[t] for t in ts] for _, ts in original.quads]
    mesh = se.quad_mesh("cloth", original.positions, faces, face_uvs)
    assert [ps for ps, _ in mesh.quads] == faces
    assert len(mesh.uvs) == len(set(original.uvs))
    for (_, ta), (_, tb) in zip(mesh.quads, original.quads):
        assert [mesh.uvs[t] for t in ta] == [original.uvs[t] for t in tb]


def test_non_quad_face_names_object_and_face():
    positions = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0)]
    faces = [(0, 1, 2, 3), (1, 4, 2)]
    uvs = [[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 0), (1, 0), (1, 1)]]
    with pytest.raises(ClothbakeError) as e:
        se.quad_mesh("sheet", positions, faces, uvs)
    assert str(e.value) == ("object 'sheet': face 1 has 3 corners; clothbake needs quads "
                            "(4 corners)")
    with pytest.raises(ClothbakeError, match="object 'sheet': the mesh has no UV map"):
        se.quad_mesh("sheet", positions, faces[:1], None)


def model_of(scene_path, float32=True):
    """An export model of a scene as a Blender round trip would build it."""
    scene = load_scene(scene_path)
    b = blender_camera(scene["camera"])
    cam = se.camera_from_blender(as_float32(b["matrix"]), f32(b["lens"]), b["sensor_width"],
                                 b["sensor_height"], b["sensor_fit"], b["resolution"],
                                 hint=scene["camera"])
    lights = []
    for i, light in enumerate(scene["lights"]):
        bl = blender_light(light)
        lights.append(se.light_from_blender(f"l{i}", bl["type"], as_float32(bl["matrix"]),
                                            bl["color"], f32(bl["energy"]), hint=light))
    objects = []
    for o in scene["objects"]:
        mesh = read_obj(o["mesh_path"])
        positions = [tuple(f32(c) for c in p) for p in mesh.positions] if float32 else \
            mesh.positions
        faces = [ps for ps, _ in mesh.quads]
        face_uvs = [[mesh.uvs[t] for t in ts] for _, ts in mesh.quads]
        entry = {k: f32(o[k]) for k in se.OBJECT_KEYS}
        entry.update(name=o["name"], mesh=se.quad_mesh(o["name"], positions, faces, face_uvs),
                     cloth=o.get("cloth_path", o.get("cloth")),
                     isotropic_albedo=o["isotropic_albedo"], volume=o.get("volume_path"))
        objects.append(entry)
    return se.build_scene(cam, lights, objects, scene["background"],
                          scene["json"].get("render"), name=scene["name"])


@pytest.mark.parametrize("scene", [PAPER, SLAB])
def test_written_scene_reads_back_the_same(tmp_path, scene):
    model = model_of(scene)
    out = se.write_scene(model, tmp_path / "exported" / "scene.json")
    assert sorted(os.listdir(tmp_path / "exported")) == sorted(
        ["scene.json"] + se.mesh_filenames(model))  # no temporary files left
    back, orig = load_scene(out), load_scene(scene)
    assert back["camera"] == orig["camera"]
    assert back["lights"] == orig["lights"]
    for a, b in zip(back["objects"], orig["objects"]):
        for k in se.OBJECT_KEYS:
            assert a[k] == b[k]
        assert a["cloth_path"] == b["cloth_path"]  # the same spec file, referred to relatively
        assert not os.path.isabs(json.load(open(out))["objects"][0]["cloth"])
    assert se.scene_matches_file(model, scene)
    assert se.scene_matches_file(model, out)


def test_scene_matches_file_sees_changes():
    model = model_of(PAPER)
    model["objects"][0]["thickness_world"] = 0.02
    assert not se.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["render"]["spp"] = 5
    assert not se.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["objects"][0]["mesh"].positions[0] = (9.0, 9.0, 9.0)
    assert not se.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["objects"][0]["cloth"] = {"weave": {"pattern": "twill_2_2"}}
    assert not se.scene_matches_file(model, PAPER)
    assert not se.scene_matches_file(model_of(PAPER), "/nonexistent/scene.json")


def test_write_is_atomic_on_failure(tmp_path):
    model = model_of(SLAB)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(ClothbakeError, match="cannot create the folder"):
        se.write_scene(model, blocker / "scene.json")


def test_empty_scene_is_refused():
    cam = load_scene(SLAB)["camera"]
    with pytest.raises(ClothbakeError, match="objects: a clothbake scene needs at least one "
                                             "cloth object"):
        se.build_scene(cam, [{"type": "point"}], [], [0, 0, 0])
    with pytest.raises(ClothbakeError, match="lights: "):
        se.build_scene(cam, [], [], [0, 0, 0])


def test_mesh_filenames_are_unique_and_safe():
    model = {"objects": [{"name": "a b"}, {"name": "a_b"}, {"name": "../x"}, {"name": ""}]}
    assert se.mesh_filenames(model) == ["a_b.obj", "a_b_2.obj", "x.obj", "object.obj"]


def test_clothbake_accepts_the_export(tmp_path, clothbake_bin):
    model = model_of(SLAB)
    model["render"]["spp"] = 1
    out = se.write_scene(model, tmp_path / "scene.json")
    run = subprocess.run([clothbake_bin, "render", out, "-o", str(tmp_path / "r.exr"),
                          "--quiet", "--threads", "1"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert os.path.getsize(tmp_path / "r.exr") > 0


def test_a_vdb_texture_round_trips_and_renders(tmp_path, clothbake_bin):
    """An object whose texture is read from a VDB keeps it through import and
    export (relative to the new scene file), and the program renders the
    exported scene exactly as the original."""
    vdb_dir = tmp_path / "vdb"
    subprocess.run([clothbake_bin, "volume", os.path.join(os.path.dirname(SLAB), "cloth.json"),
                    "-o", str(vdb_dir)], check=True, stdout=subprocess.DEVNULL)
    original = json.load(open(SLAB))
    original["objects"][0]["volume"] = str(vdb_dir / "volume.vdb")
    for key in ("mesh", "cloth"):
        original["objects"][0][key] = os.path.join(os.path.dirname(SLAB),
                                                   original["objects"][0][key])
    original["render"] = dict(original.get("render", {}), spp=1)
    source = tmp_path / "source" / "scene.json"
    source.parent.mkdir()
    source.write_text(json.dumps(original))
    assert load_scene(source)["objects"][0]["volume_path"] == str(vdb_dir / "volume.vdb")

    model = model_of(source)
    out = se.write_scene(model, tmp_path / "exported" / "scene.json")
    assert json.load(open(out))["objects"][0]["volume"] == os.path.join("..", "vdb", "volume.vdb")
    assert load_scene(out)["objects"][0]["volume_path"] == str(vdb_dir / "volume.vdb")
    assert se.scene_matches_file(model, source) and se.scene_matches_file(model, out)
    model["objects"][0]["volume"] = None
    assert not se.scene_matches_file(model, source)

    images = []
    for scene in (source, Path(out)):
        image = tmp_path / (scene.parent.name + ".exr")
        run = subprocess.run([clothbake_bin, "render", str(scene), "-o", str(image), "--quiet",
                              "--threads", "1"], capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        images.append(image.read_bytes())
    assert images[0] == images[1]
