"""OBJ and scene reading in the add-on, and the camera conversion to
Blender's conventions."""
import math
import os

import pytest

from clothbake.core.errors import ClothbakeError
from clothbake.core.light_units import BLENDER_3
from clothbake.core.obj import format_obj, read_obj
from clothbake.core import scene as sc


def test_reads_the_paper_cloth_in_file_order(source_dir):
    mesh = read_obj(os.path.join(source_dir, "testscenes", "paper", "cloth.obj"))
    assert len(mesh.quads) == 64 and len(mesh.positions) == 81 and len(mesh.uvs) == 81
    ps, ts = mesh.quads[0]
    assert len(ps) == 4 and len(ts) == 4


@pytest.mark.parametrize("text,message", [
    ("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
     "line 5: face has 3 corners; clothbake needs quads (4 corners)"),
    ("v 0 0 0\nv 1 0 x\n", "line 2: malformed number 'x' in vertex"),
    ("v 0 0 nan\n", "line 1: non-finite number 'nan' in vertex"),
    ("v 0 0 0\nvt 0 0\nf 1/1 1/1 1/1 9/1\n", "line 3: vertex index 9 out of range (1..1)"),
    ("v 0 0 0\nf 1 1 1 1\n", "line 2: face corner '1' has no UV index"),
    ("v 0 0 0\nl 1 1\n", "line 2: unsupported statement 'l'"),
    ("# nothing\n", "mesh has no faces"),
])
def test_refuses_bad_meshes_naming_the_line(tmp_path, text, message):
    path = tmp_path / "bad.obj"
    path.write_text(text)
    with pytest.raises(ClothbakeError) as err:
        read_obj(path)
    assert message in str(err.value) and str(path) in str(err.value)


def test_obj_round_trip(tmp_path, source_dir):
    mesh = read_obj(os.path.join(source_dir, "testscenes", "paper", "cloth.obj"))
    path = tmp_path / "copy.obj"
    path.write_text(format_obj(mesh))
    again = read_obj(path)
    assert again.quads == mesh.quads
    assert again.positions == pytest.approx(mesh.positions)




def project(settings, point):
    """Pixel position of a world point through a Blender camera (matrix,
    lens, sensor), x right and y down from the top-left corner."""
    m = settings["matrix"]
    d = [point[r] - m[r][3] for r in range(3)]
    cam = [sum(m[r][c] * d[r] for r in range(3)) for c in range(3)]  # transpose: world -> camera
    width, height = settings["resolution"]
    sensor = settings["sensor_width"] if settings["sensor_fit"] == "HORIZONTAL" else \
        settings["sensor_height"]
    extent = width if settings["sensor_fit"] == "HORIZONTAL" else height
    focal_px = settings["lens"] / sensor * extent
    return (0.5 * width + focal_px * cam[0] / -cam[2], 0.5 * height - focal_px * cam[1] / -cam[2])


@pytest.mark.parametrize("axis", ["horizontal", "vertical"])
def test_blender_camera_reproduces_the_pinhole(axis):
    cam = {"position": [-1.3, 0.7, 3.5], "look_at": [-0.1, -0.62, -0.1], "up": [0, 1, 0],
           "fov_deg": 43.0, "fov_axis": axis, "resolution": [426, 266]}
    settings = sc.blender_camera(cam)
    m = settings["matrix"]
    cols = [[m[r][c] for r in range(3)] for c in range(3)]
    for a in range(3):
        for b in range(3):
            assert sum(x * y for x, y in zip(cols[a], cols[b])) == pytest.approx(float(a == b))
    # The look-at point is the image centre; the field of view spans the axis.
    assert project(settings, cam["look_at"]) == pytest.approx((213.0, 133.0))
    right, up, forward = sc.camera_basis(cam)
    half = math.tan(math.radians(43.0) / 2)
    across = right if axis == "horizontal" else up
    edge = [p + f + half * a for p, f, a in zip(cam["position"], forward, across)]
    x, y = project(settings, edge)
    if axis == "horizontal":
        assert x == pytest.approx(426.0)
    else:
        assert y == pytest.approx(0.0)


def test_loads_the_paper_scene(source_dir):
    model = sc.load_scene(os.path.join(source_dir, "testscenes", "paper", "scene.json"))
    assert model["camera"]["resolution"] == [426, 266]
    assert [l["type"] for l in model["lights"]] == ["directional", "point"]
    (obj,) = model["objects"]
    assert os.path.isfile(obj["mesh_path"]) and os.path.isfile(obj["cloth_path"])
    sun = sc.blender_light(model["lights"][0], BLENDER_3)
    # Blender's sun shines along its local -Z: the matrix's third column is -direction.
    z = [sun["matrix"][r][2] for r in range(3)]
    d = model["lights"][0]["direction"]
    n = math.sqrt(sum(c * c for c in d))
    assert z == pytest.approx([-c / n for c in d])
    assert sun["energy"] == 3.0
    # A Cycles point lamp of P watts gives irradiance P / (4 pi) at 1 unit
    # (measured: lab/light_units/light_units.py), so intensity 8 needs 32 pi W.
    point = sc.blender_light(model["lights"][1], BLENDER_3)
    assert point["energy"] == pytest.approx(8.0 * 4.0 * math.pi, rel=1e-12)


@pytest.mark.parametrize("edit,message", [
    ('"camera": 3', "camera: missing or not an object"),
    ('"lights": []', "lights: must be a non-empty array"),
    ('"camera": {"fov_axis": "diagonal"}', "camera.fov_axis: must be 'horizontal' or 'vertical'"),
    ('"camera": {"position": [0, 0]}', "camera.position: must be an array of 3 numbers"),
    ('"render": 5', "render: must be an object"),
    ('"render": {"spp": "many"}', "render.spp: must be an integer"),
    ('"render": {"fiber_samples": 0}', "render.fiber_samples: must be in [1, 65536], got 0"),
    ('"render": {"seed": 4294967296}', "render.seed: must be in [0, 2147483647], got 4294967296"),
    ('"render": {"shading": "toon"}',
     'render.shading: unknown value "toon"; expected one of: fiber, isotropic'),
    ('"render": {"cutoff": "small"}', "render.cutoff: must be a finite number"),
    ('"objects": [{"name": 3, "mesh": "a.obj", "cloth": {}}]',
     "objects[0].name: must be a non-empty string"),
    ('"objects": [{"mesh": "a.obj", "cloth": {}, "isotropic_albedo": 0.5}]',
     "objects[0].isotropic_albedo: must be an array of 3 numbers"),
    ('"objects": [{"mesh": "a.obj", "cloth": {"weft": {"color": "red"}}}]',
     "objects[0].cloth.weft.color: must be an array of 3 numbers"),
    ('"objects": [{"mesh": "a.obj", "cloth": {}, "volume": 7}]',
     "objects[0].volume: must be the path of a VDB file"),
    ('"objects": [{"mesh": "a.obj", "cloth": {}, "volume": "none.vdb"}]',
     "objects[0].volume: the VDB file"),
    ('"lights": [{"type": "spot", "position": [0, 1, 0]}]',
     "lights[0].direction: must be an array of 3 numbers"),
    ('"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, 0, -1], '
     '"spot_blend": "soft"}]', "lights[0].spot_blend: must be a finite number"),
    ('"lights": [{"type": "area", "position": [0, 1, 0], "direction": [0, 0, -1], '
     '"x_axis": [1, 0, 0], "shape": "star", "size": 1}]',
     'lights[0].shape: unknown shape "star"; expected one of: rectangle, square, disk, ellipse'),
    ('"lights": [{"type": "area", "position": [0, 1, 0], "direction": [0, 0, -1], '
     '"x_axis": [1, 0, 0], "shape": "rectangle", "size": 1}]',
     "lights[0].size: must be an array of 2 numbers"),
    ('"lights": [{"type": "area", "position": [0, 1, 0], "direction": [0, 0, -1], '
     '"shape": "disk", "size": 1}]', "lights[0].x_axis: must be an array of 3 numbers"),
    ('"lights": [{"type": "hemi", "position": [0, 1, 0]}]',
     "lights[0].type: must be an object with type 'directional', 'point', 'spot' or 'area'"),
])
def test_refuses_bad_scenes(tmp_path, edit, message):
    path = tmp_path / "scene.json"
    base = ('{"lights": [{"type": "point", "position": [0, 1, 0]}], '
            '"objects": [{"mesh": "a.obj", "cloth": {}}], "camera": {}}')
    key = edit.split(":")[0]
    import json
    root = json.loads(base)
    root.update(json.loads("{" + edit + "}"))
    path.write_text(json.dumps(root))
    with pytest.raises(ClothbakeError) as err:
        sc.load_scene(path)
    assert message in str(err.value)
