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
from clothbake.core import scene_match as sm  # noqa: E402
from clothbake.core.errors import ClothbakeError  # noqa: E402
from clothbake.core.obj import read_obj  # noqa: E402
from clothbake.core.light_units import (BLENDER_3, BLENDER_4, effective_watts,  # noqa: E402
                                        light_units, unsupported_light_setting)
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
    assert sm.same_camera(out, cam)


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
    assert not sm.same_camera(out, cam)


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
        b = blender_light(light, BLENDER_3)
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


SPOT_AND_AREA = [
    {"type": "spot", "position": [0.3, -1.2, 2.5], "direction": [0.1, 0.4, -1.0],
     "spot_size_deg": 52.5, "spot_blend": 0.3, "color": [1.0, 0.9, 0.7], "intensity": 2.5},
    {"type": "area", "position": [-1.0, 0.5, 1.7], "direction": [0.3, -0.2, -0.9],
     "x_axis": [1.0, 0.0, 0.333], "shape": "rectangle", "size": [0.8, 0.35],
     "color": [0.7, 0.8, 1.0], "intensity": 3.0},
    {"type": "area", "position": [0.0, 0.0, 2.0], "direction": [0.0, 0.0, -1.0],
     "x_axis": [0.0, 1.0, 0.0], "shape": "disk", "size": 0.6, "color": [1, 1, 1],
     "intensity": 1.5},
    {"type": "area", "position": [2.0, 0.0, 1.0], "direction": [-1.0, 0.0, -0.5],
     "x_axis": [0.0, 1.0, 0.0], "shape": "ellipse", "size": [1.2, 0.4], "color": [1, 1, 1],
     "intensity": 1.0},
    {"type": "area", "position": [0.0, 2.0, 1.0], "direction": [0.0, -1.0, 0.0],
     "x_axis": [1.0, 0.0, 0.0], "shape": "square", "size": 0.25, "color": [1, 1, 1],
     "intensity": 9.0},
]


def blender_settings(b):
    """What the Blender side hands light_from_blender for a light's data."""
    if b["type"] == "SPOT":
        return {"spot_size": b["spot_size"], "spot_blend": b["spot_blend"]}
    if b["type"] == "AREA":
        return {"shape": b["shape"], "size": b["size"], "size_y": b["size_y"],
                "spread": math.pi}
    return None


def _f32_settings(settings):
    return {k: f32(v) if isinstance(v, float) else v for k, v in settings.items()}


@pytest.mark.parametrize("float32", [False, True])
@pytest.mark.parametrize("light", SPOT_AND_AREA, ids=lambda l: l["type"] + "-" +
                         str(l.get("shape", "")))
def test_spot_and_area_lights_round_trip(float32, light):
    b = blender_light(light, BLENDER_3)
    matrix = as_float32(b["matrix"]) if float32 else b["matrix"]
    settings = blender_settings(b)
    energy = f32(b["energy"]) if float32 else b["energy"]
    if float32:
        settings = _f32_settings(settings)
    plain = se.light_from_blender("l", b["type"], matrix, b["color"], energy, settings=settings)
    assert plain["type"] == light["type"]
    assert abs(plain["intensity"] - light["intensity"]) <= 1e-6 * light["intensity"]
    assert_vec(plain["position"], light["position"], 1e-6)
    d = light["direction"]
    n = math.sqrt(sum(c * c for c in d))
    assert_vec(plain["direction"], [c / n for c in d], 1e-6)
    if light["type"] == "spot":
        assert abs(plain["spot_size_deg"] - light["spot_size_deg"]) <= 1e-4
        assert abs(plain["spot_blend"] - light["spot_blend"]) <= 1e-6
    else:
        assert plain["shape"] == light["shape"]
        size = light["size"] if isinstance(light["size"], list) else [light["size"]]
        got = plain["size"] if isinstance(plain["size"], list) else [plain["size"]]
        assert_vec(got, size, 1e-6)
        # x_axis: the given one made orthogonal to the direction
        x = light["x_axis"]
        dn = [c / n for c in d]
        dot = sum(a * c for a, c in zip(x, dn))
        xo = [a - dot * c for a, c in zip(x, dn)]
        xn = math.sqrt(sum(c * c for c in xo))
        assert_vec(plain["x_axis"], [c / xn for c in xo], 1e-6)
    hinted = se.light_from_blender("l", b["type"], matrix, b["color"], energy, hint=light,
                                   settings=settings)
    if light["type"] == "area" and light["x_axis"] != [1.0, 0.0, 0.333]:
        assert hinted == light
    elif light["type"] == "spot":
        assert hinted == light


def test_light_watts():
    """Blender's watts: a spot's as a point light's (4 pi per unit of
    intensity), an area light's 4 per unit of radiant intensity (measured:
    Cycles 3.4 gives radiance P / (4 A); docs/design/blender-nodes.md)."""
    spot, area = SPOT_AND_AREA[0], SPOT_AND_AREA[1]
    assert blender_light(spot, BLENDER_3)["energy"] == pytest.approx(2.5 * 4 * math.pi,
                                                                     rel=1e-12)
    assert blender_light(area, BLENDER_3)["energy"] == pytest.approx(12.0, rel=1e-12)
    b = blender_light(spot, BLENDER_3)
    assert b["spot_size"] == pytest.approx(math.radians(52.5)) and b["spot_blend"] == 0.3
    # -Z along the direction, a rotation (orthonormal, right-handed)
    m = b["matrix"]
    cols = [[m[r][c] for r in range(3)] for c in range(3)]
    d = spot["direction"]
    n = math.sqrt(sum(c * c for c in d))
    assert_vec([-c for c in cols[2]], [c / n for c in d], 1e-12)
    for i in range(3):
        for j in range(3):
            assert abs(sum(a * b for a, b in zip(cols[i], cols[j])) - (i == j)) < 1e-12
    cx = [cols[0][1] * cols[1][2] - cols[0][2] * cols[1][1],
          cols[0][2] * cols[1][0] - cols[0][0] * cols[1][2],
          cols[0][0] * cols[1][1] - cols[0][1] * cols[1][0]]
    assert_vec(cx, cols[2], 1e-12)


def test_light_watts_from_blender_4():
    """From Blender 4.0 an area light of P watts has radiance P / (pi A)
    and a spot's mask lacks 3.x's cosine off the axis (measured in 4.3.2
    and 5.2.2: lab/light_units/): the same clothbake light takes pi / 4 of
    the area watts, the spot's watts are a point light's, and the spot is
    written with axis_cosine false. Both round-trip in their own units."""
    assert light_units((3, 4, 1)) is BLENDER_3 and light_units((3, 6, 0)) is BLENDER_3
    assert light_units((4, 0, 0)) is BLENDER_4 and light_units((5, 2, 2)) is BLENDER_4
    spot, area = SPOT_AND_AREA[0], SPOT_AND_AREA[1]
    assert blender_light(area, BLENDER_4)["energy"] == pytest.approx(3.0 * math.pi, rel=1e-12)
    b = blender_light(spot, BLENDER_4)
    assert b["energy"] == pytest.approx(2.5 * 4 * math.pi, rel=1e-12)
    assert "mask" in b     # a spot written for 3.x, made in 4.x: noted
    back = se.light_from_blender("s", "SPOT", b["matrix"], b["color"], b["energy"],
                                 settings={"spot_size": b["spot_size"],
                                           "spot_blend": b["spot_blend"]}, units=BLENDER_4)
    assert back["axis_cosine"] is False
    assert back["intensity"] == pytest.approx(spot["intensity"], rel=1e-12)
    assert "mask" not in blender_light(back, BLENDER_4)
    a = blender_light(area, BLENDER_4)
    back = se.light_from_blender("a", "AREA", a["matrix"], a["color"], a["energy"],
                                 settings={"shape": a["shape"], "size": a["size"],
                                           "size_y": a["size_y"]}, units=BLENDER_4)
    assert back["intensity"] == pytest.approx(area["intensity"], rel=1e-12)
    assert "axis_cosine" not in se.light_from_blender(
        "s", "SPOT", b["matrix"], b["color"], b["energy"],
        settings={"spot_size": 1.0, "spot_blend": 0.1}, units=BLENDER_3)


def test_light_exposure_and_unsupported_settings():
    """Exposure (5.x) multiplies the watts by 2^exposure; Temperature on
    or Normalize off (5.x) is refused naming the light and the setting."""
    assert effective_watts(10.0) == 10.0
    assert effective_watts(10.0, 2.0) == pytest.approx(40.0)
    assert effective_watts(10.0, -1.0) == pytest.approx(5.0)
    assert unsupported_light_setting() is None
    with pytest.raises(ClothbakeError) as e:
        se.light_from_blender("warm", "POINT", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2],
                                                [0, 0, 0, 1]], [1, 1, 1], 10.0,
                              unsupported=unsupported_light_setting(use_temperature=True))
    assert "light 'warm'" in str(e.value) and "Temperature" in str(e.value)
    assert "Normalize" in unsupported_light_setting(normalize=False)


def _scaled(matrix, sx, sy, sz=1.0):
    return [[row[0] * sx, row[1] * sy, row[2] * sz, row[3]] for row in matrix[:3]] + [matrix[3]]


def test_area_size_follows_the_object_scale():
    """The sides are size (size_y) times the world matrix's scale along X
    (Y); a square or disk scaled unevenly is a rectangle or an ellipse."""
    square = dict(SPOT_AND_AREA[4])
    b = blender_light(square, BLENDER_3)
    out = se.light_from_blender("sq", "AREA", _scaled(b["matrix"], 2.0, 2.0, 5.0), [1, 1, 1],
                                b["energy"], settings=blender_settings(b))
    assert out["shape"] == "square" and out["size"] == pytest.approx(0.5)
    out = se.light_from_blender("sq", "AREA", _scaled(b["matrix"], 2.0, 3.0), [1, 1, 1],
                                b["energy"], settings=blender_settings(b))
    assert out["shape"] == "rectangle" and out["size"] == pytest.approx([0.5, 0.75])
    disk = blender_light(SPOT_AND_AREA[2], BLENDER_3)
    out = se.light_from_blender("d", "AREA", _scaled(disk["matrix"], 1.0, 0.5), [1, 1, 1],
                                disk["energy"], settings=blender_settings(disk))
    assert out["shape"] == "ellipse" and out["size"] == pytest.approx([0.6, 0.3])
    assert out["intensity"] == pytest.approx(1.5)   # the power is kept, not the radiance
    # a spot scaled evenly is the same spot (Cycles ignores its scale)
    spot = blender_light(SPOT_AND_AREA[0], BLENDER_3)
    out = se.light_from_blender("s", "SPOT", _scaled(spot["matrix"], 3.0, 3.0, 3.0),
                                spot["color"], spot["energy"], settings=blender_settings(spot))
    assert_vec(out["position"], SPOT_AND_AREA[0]["position"], 1e-12)
    assert out["spot_size_deg"] == pytest.approx(52.5)


def test_what_clothbake_cannot_model_is_refused_naming_light_and_setting():
    spot = blender_light(SPOT_AND_AREA[0], BLENDER_3)
    with pytest.raises(ClothbakeError, match=r"^light 'cone': scale: its X and Y scale differ "
                                             r"\(2, 1\): Eevee draws that cone as an ellipse"):
        se.light_from_blender("cone", "SPOT", _scaled(spot["matrix"], 2.0, 1.0), [1, 1, 1],
                              100.0, settings=blender_settings(spot))
    area = blender_light(SPOT_AND_AREA[1], BLENDER_3)
    settings = dict(blender_settings(area), spread=math.radians(90.0))
    with pytest.raises(ClothbakeError, match=r"^light 'panel': spread: 90 degrees; clothbake's "
                                             "area lights emit into the whole half-space"):
        se.light_from_blender("panel", "AREA", area["matrix"], [1, 1, 1], 10.0,
                              settings=settings)
    sheared = [row[:] for row in area["matrix"]]
    for r in range(3):
        sheared[r][1] += 0.3 * sheared[r][0]
    with pytest.raises(ClothbakeError, match=r"^light 'panel': its world matrix is sheared"):
        se.light_from_blender("panel", "AREA", sheared, [1, 1, 1], 10.0,
                              settings=blender_settings(area))
    with pytest.raises(ClothbakeError, match="light 'lamp': hemi lights are not supported; "
                                             "clothbake has sun"):
        se.light_from_blender("lamp", "HEMI", [[1, 0, 0, 0]] * 4, [1, 1, 1], 1)


def test_spot_and_area_lights_in_a_written_scene_read_back(tmp_path):
    model = model_of(SLAB)
    for light in SPOT_AND_AREA:
        b = blender_light(light, BLENDER_3)
        model["lights"].append(se.light_from_blender(
            "l", b["type"], as_float32(b["matrix"]), b["color"], f32(b["energy"]), hint=light,
            settings=_f32_settings(blender_settings(b))))
    out = se.write_scene(model, tmp_path / "scene.json")
    back = load_scene(out)
    assert back["lights"][-len(SPOT_AND_AREA):][0] == SPOT_AND_AREA[0]
    assert sm.scene_matches_file(model, out)
    model["lights"][-1] = dict(model["lights"][-1], size=0.3)
    assert not sm.scene_matches_file(model, out)
    model["lights"][-1] = dict(model["lights"][-1], size=0.25, shape="disk")
    assert not sm.scene_matches_file(model, out)


def test_clothbake_accepts_spot_and_area_lights(tmp_path, clothbake_bin):
    model = model_of(SLAB)
    model["render"]["spp"] = 1
    model["lights"] = [dict(l) for l in SPOT_AND_AREA]
    out = se.write_scene(model, tmp_path / "scene.json")
    run = subprocess.run([clothbake_bin, "render", out, "-o", str(tmp_path / "r.exr"),
                          "--quiet", "--threads", "1"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


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
        bl = blender_light(light, BLENDER_3)
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
    assert sm.scene_matches_file(model, scene)
    assert sm.scene_matches_file(model, out)


def test_scene_matches_file_sees_changes():
    model = model_of(PAPER)
    model["objects"][0]["thickness_world"] = 0.02
    assert not sm.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["render"]["spp"] = 5
    assert not sm.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["objects"][0]["mesh"].positions[0] = (9.0, 9.0, 9.0)
    assert not sm.scene_matches_file(model, PAPER)
    model = model_of(PAPER)
    model["objects"][0]["cloth"] = {"weave": {"pattern": "twill_2_2"}}
    assert not sm.scene_matches_file(model, PAPER)
    assert not sm.scene_matches_file(model_of(PAPER), "/nonexistent/scene.json")


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
    assert sm.scene_matches_file(model, source) and sm.scene_matches_file(model, out)
    model["objects"][0]["volume"] = None
    assert not sm.scene_matches_file(model, source)

    images = []
    for scene in (source, Path(out)):
        image = tmp_path / (scene.parent.name + ".exr")
        run = subprocess.run([clothbake_bin, "render", str(scene), "-o", str(image), "--quiet",
                              "--threads", "1"], capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        images.append(image.read_bytes())
    assert images[0] == images[1]
