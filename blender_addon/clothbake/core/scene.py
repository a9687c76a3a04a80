"""clothbake scene JSON (docs/formats/scene.md) as the add-on needs it: read
with clear errors, the camera and lights converted to Blender's
conventions, and written back for export.

clothbake's program is the authority on what a valid scene is; this reader
checks what the add-on itself relies on (types and shapes), and leaves
ranges to the program, which names the field when it refuses.
"""
import json
import math
import os

from . import defaults
from .cloth_fields import fields_from_spec
from .errors import ClothbakeError

CAMERA_DEFAULTS = {"position": [0.0, 0.0, 5.0], "look_at": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0],
                   "fov_deg": 40.0, "fov_axis": "horizontal", "resolution": [426, 266]}
OBJECT_DEFAULTS = {"repeats_per_uv": 40.0, "thickness_world": 0.01, "extinction_per_mm": 40.0,
                   "isotropic_albedo": [0.8, 0.8, 0.8]}
RENDER_DEFAULTS = defaults.RENDER_DEFAULTS  # the program's (core/defaults.py)
FIBER_MODELS = ("ellipsoid", "table", "kajiya-kay")
TRANSMITTANCES = ("shadow-march", "cached")
SHADINGS = ("fiber", "isotropic")
_RENDER_CHOICES = {"fiber_model": FIBER_MODELS, "transmittance": TRANSMITTANCES,
                   "shading": SHADINGS}
_MAX_SAMPLES = 65536
_MAX_SEED = 2**31 - 1  # what a Blender IntProperty holds

# Blender's watts as clothbake's intensities, per Blender version: light_units.py.


def _vec(value, n, path, field):
    if (not isinstance(value, list) or len(value) != n or
            not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
        raise ClothbakeError(f"must be an array of {n} numbers", path, field)
    if not all(math.isfinite(v) for v in value):
        raise ClothbakeError("must be finite", path, field)
    return [float(v) for v in value]


def _num(value, path, field):
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
        raise ClothbakeError("must be a finite number", path, field)
    return float(value)


def _render(value, path):
    """The "render" block, checked as far as the add-on's settings hold it
    (an enum, an int property): a value they cannot take is refused here,
    never clamped or left to fail in Blender."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ClothbakeError("must be an object", path, "render")
    for key, v in value.items():
        field = f"render.{key}"
        if key in _RENDER_CHOICES:
            if not isinstance(v, str) or v not in _RENDER_CHOICES[key]:
                raise ClothbakeError(f"unknown value {json.dumps(v)}; expected one of: "
                                     + ", ".join(_RENDER_CHOICES[key]), path, field)
        elif key in ("spp", "fiber_samples", "seed"):
            lo, hi = (0, _MAX_SEED) if key == "seed" else (1, _MAX_SAMPLES)
            if not isinstance(v, int) or isinstance(v, bool):
                raise ClothbakeError("must be an integer", path, field)
            if not lo <= v <= hi:
                raise ClothbakeError(f"must be in [{lo}, {hi}], got {v}", path, field)
        elif key in ("step_cells", "cutoff"):
            _num(v, path, field)
    return value


def _read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            root = json.load(f)
    except OSError as e:
        raise ClothbakeError(f"cannot read the scene: {e.strerror}", path) from None
    except UnicodeDecodeError as e:
        raise ClothbakeError(f"not UTF-8 text (byte {e.start}); a scene is a JSON file",
                             path) from None
    except json.JSONDecodeError as e:
        raise ClothbakeError(f"invalid JSON: {e.msg}", path, f"line {e.lineno}") from None
    if not isinstance(root, dict):
        raise ClothbakeError("must be a JSON object", path)
    return root


def _camera(root, path):
    """The camera block, defaults filled in and checked."""
    cam_json = root.get("camera")
    if not isinstance(cam_json, dict):
        raise ClothbakeError("missing or not an object", path, "camera")
    cam = dict(CAMERA_DEFAULTS)
    cam.update(cam_json)
    for key in ("position", "look_at", "up"):
        cam[key] = _vec(cam[key], 3, path, f"camera.{key}")
    cam["fov_deg"] = _num(cam["fov_deg"], path, "camera.fov_deg")
    if cam["fov_axis"] not in ("horizontal", "vertical"):
        raise ClothbakeError("must be 'horizontal' or 'vertical'", path, "camera.fov_axis")
    res = cam["resolution"]
    if (not isinstance(res, list) or len(res) != 2 or
            not all(isinstance(v, int) and not isinstance(v, bool) and v >= 1 for v in res)):
        raise ClothbakeError("must be [width, height], integers >= 1", path, "camera.resolution")
    return cam


LIGHT_TYPES = ("directional", "point", "spot", "area")
AREA_SHAPES = ("rectangle", "square", "disk", "ellipse")
SPOT_DEFAULTS = {"spot_size_deg": 45.0, "spot_blend": 0.15}  # the program's (light_json.cpp)


def _spot(lj, light, path, where):
    light["position"] = _vec(lj.get("position"), 3, path, where + ".position")
    light["direction"] = _vec(lj.get("direction"), 3, path, where + ".direction")
    for key, default in SPOT_DEFAULTS.items():
        light[key] = _num(lj.get(key, default), path, f"{where}.{key}")
    axis_cosine = lj.get("axis_cosine", True)
    if not isinstance(axis_cosine, bool):
        raise ClothbakeError("must be true or false", path, where + ".axis_cosine")
    if not axis_cosine:     # kept off its default only, as export writes it
        light["axis_cosine"] = False


def _area(lj, light, path, where):
    light["position"] = _vec(lj.get("position"), 3, path, where + ".position")
    light["direction"] = _vec(lj.get("direction"), 3, path, where + ".direction")
    light["x_axis"] = _vec(lj.get("x_axis"), 3, path, where + ".x_axis")
    shape = lj.get("shape", "rectangle")
    if shape not in AREA_SHAPES:
        raise ClothbakeError(f"unknown shape {json.dumps(shape)}; expected one of: "
                             + ", ".join(AREA_SHAPES), path, where + ".shape")
    light["shape"] = shape
    if shape in ("square", "disk"):
        light["size"] = _num(lj.get("size"), path, where + ".size")
    else:
        light["size"] = _vec(lj.get("size"), 2, path, where + ".size")


def _lights(root, path):
    """The lights, each a dict of type, color, intensity and its direction
    or position (spot: position, direction, spot_size_deg, spot_blend; area:
    position, direction, x_axis, shape, size)."""
    lights = []
    lights_json = root.get("lights")
    if not isinstance(lights_json, list) or not lights_json:
        raise ClothbakeError("must be a non-empty array", path, "lights")
    for i, lj in enumerate(lights_json):
        where = f"lights[{i}]"
        if not isinstance(lj, dict) or lj.get("type") not in LIGHT_TYPES:
            raise ClothbakeError("must be an object with type 'directional', 'point', 'spot' "
                                 "or 'area'", path, where + ".type")
        light = {"type": lj["type"],
                 "color": _vec(lj.get("color", [1.0, 1.0, 1.0]), 3, path, where + ".color"),
                 "intensity": _num(lj.get("intensity", 1.0), path, where + ".intensity")}
        if light["type"] == "directional":
            light["direction"] = _vec(lj.get("direction"), 3, path, where + ".direction")
        elif light["type"] == "point":
            light["position"] = _vec(lj.get("position"), 3, path, where + ".position")
        elif light["type"] == "spot":
            _spot(lj, light, path, where)
        else:
            _area(lj, light, path, where)
        lights.append(light)
    return lights


def _object(oj, where, folder, path):
    """objects[i] with defaults filled in and its paths made absolute."""
    if not isinstance(oj, dict):
        raise ClothbakeError("must be an object", path, where)
    obj = dict(OBJECT_DEFAULTS)
    obj.update(oj)
    obj["name"] = oj.get("name", where)
    if not isinstance(obj["name"], str) or not obj["name"]:
        raise ClothbakeError("must be a non-empty string", path, where + ".name")
    mesh = oj.get("mesh")
    if not isinstance(mesh, str) or not mesh:
        raise ClothbakeError("must be the path of an OBJ file", path, where + ".mesh")
    obj["mesh_path"] = os.path.normpath(os.path.join(folder, mesh))
    if "volume" in oj:
        # A texture read from a VDB (docs/formats/scene.md): kept as a path
        # and written back on export; the cloth spec still gives the fibre
        # model. The program reads and checks the file when it renders.
        volume = oj["volume"]
        if not isinstance(volume, str) or not volume:
            raise ClothbakeError("must be the path of a VDB file", path, where + ".volume")
        obj["volume_path"] = os.path.normpath(os.path.join(folder, volume))
        if not os.path.isfile(obj["volume_path"]):
            raise ClothbakeError(f"the VDB file {obj['volume_path']} does not exist", path,
                                 where + ".volume")
    cloth = oj.get("cloth")
    if isinstance(cloth, str):
        obj["cloth_path"] = os.path.normpath(os.path.join(folder, cloth))
    elif isinstance(cloth, dict):
        try:  # an inline spec's errors are named by their full path in the scene
            fields_from_spec(cloth, path)
        except ClothbakeError as e:
            raise ClothbakeError(e.message, path, ".".join(
                p for p in (where + ".cloth", e.field) if p)) from None
        wif = cloth.get("weave", {}).get("wif") if isinstance(cloth.get("weave"), dict) else None
        if wif is not None:  # an inline spec's weave.wif is relative to the scene file
            obj["cloth_wif_path"] = os.path.normpath(os.path.join(folder, wif))
    else:
        raise ClothbakeError("must be a cloth spec object or the path of one", path,
                             where + ".cloth")
    for key in ("repeats_per_uv", "thickness_world", "extinction_per_mm"):
        obj[key] = _num(obj[key], path, f"{where}.{key}")
    obj["isotropic_albedo"] = _vec(obj["isotropic_albedo"], 3, path,
                                   where + ".isotropic_albedo")
    return obj


def load_scene(path):
    """Reads a scene file; returns a plain dict with defaults filled in and
    mesh / cloth paths made absolute. Raises ClothbakeError."""
    path = os.path.abspath(path)
    root = _read_json(path)
    folder = os.path.dirname(path)
    cam = _camera(root, path)
    lights = _lights(root, path)
    objects_json = root.get("objects")
    if not isinstance(objects_json, list) or not objects_json:
        raise ClothbakeError("must be a non-empty array", path, "objects")
    objects = [_object(oj, f"objects[{i}]", folder, path) for i, oj in enumerate(objects_json)]
    background = _vec(root.get("background", [0.0, 0.0, 0.0]), 3, path, "background")
    render = dict(RENDER_DEFAULTS)
    render.update(_render(root.get("render"), path))
    return {"path": path, "name": root.get("name", os.path.basename(folder)), "camera": cam,
            "lights": lights, "objects": objects, "background": background, "render": render,
            "json": root}


def _sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _normalized(a):
    n = math.sqrt(sum(c * c for c in a))
    return [c / n for c in a] if n > 0 else [0.0, 0.0, 0.0]


def camera_basis(cam):
    """(right, up, forward) unit vectors, as baker/core/geometry/camera.cpp builds them."""
    forward = _normalized(_sub(cam["look_at"], cam["position"]))
    right = _cross(forward, cam["up"])
    if math.sqrt(sum(c * c for c in right)) <= 1e-6 * math.sqrt(sum(c * c for c in cam["up"])):
        f = [abs(c) for c in forward]
        axis = ([1.0, 0.0, 0.0] if f[0] <= f[1] and f[0] <= f[2] else
                [0.0, 1.0, 0.0] if f[1] <= f[2] else [0.0, 0.0, 1.0])
        right = _cross(forward, axis)
    right = _normalized(right)
    up = _cross(right, forward)
    return right, up, forward


def blender_camera(cam, sensor_mm=36.0):
    """Blender camera settings that reproduce a clothbake pinhole camera.

    Blender's camera looks along its local -Z with +Y up, so its world
    matrix has columns (right, up, -forward). The field of view is matched
    through the sensor size on the camera's fit axis: lens = sensor / 2 /
    tan(fov / 2), sensor_fit HORIZONTAL or VERTICAL as fov_axis says.
    Returns a dict: matrix (4x4 rows), lens, sensor_fit, sensor_width,
    sensor_height, resolution.
    """
    right, up, forward = camera_basis(cam)
    back = [-c for c in forward]
    p = cam["position"]
    matrix = [[right[r], up[r], back[r], p[r]] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
    fov = min(max(cam["fov_deg"], 1e-3), 180.0 - 1e-3) * math.pi / 180.0
    lens = 0.5 * sensor_mm / math.tan(0.5 * fov)
    fit = "HORIZONTAL" if cam["fov_axis"] == "horizontal" else "VERTICAL"
    return {"matrix": matrix, "lens": lens, "sensor_fit": fit, "sensor_width": sensor_mm,
            "sensor_height": sensor_mm, "resolution": list(cam["resolution"])}


def _aim_matrix(direction, position, x_axis=None):
    """A world matrix whose -Z is `direction` (the way the light travels),
    at `position`; its +X is x_axis made orthogonal to it when given."""
    d = _normalized(direction)
    z = [-c for c in d]
    x = None
    if x_axis is not None:
        dot = sum(a * b for a, b in zip(x_axis, z))
        x = _normalized([a - dot * b for a, b in zip(x_axis, z)])
        if not any(x):
            x = None
    if x is None:
        helper = [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0]
        x = _normalized(_cross(helper, d))
    y = _cross(z, x)
    p = position or [0.0, 0.0, 0.0]
    return [[x[r], y[r], z[r], p[r]] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def area_sides(light):
    """(width, height) of an area light: its size, twice for a square or disk."""
    size = light["size"]
    return (float(size[0]), float(size[1])) if isinstance(size, list) else \
        (float(size), float(size))


def blender_light(light, units):
    """Blender light settings for a clothbake light, in the LightUnits of
    the Blender that makes it (light_units.py): type, colour, energy, the
    world matrix (a sun's, spot's and area light's -Z along `direction`; an
    area light's +X along `x_axis`), and a spot's spot_size (radians) and
    spot_blend, an area light's shape, size and size_y (scale 1: the sides
    are the sizes). A spot whose cone mask is not that Blender's
    (axis_cosine) gets the note "mask" saying so: its watts are right on
    the axis only."""
    if light["type"] == "directional":
        d = _normalized(light["direction"])
        helper = [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0]
        x = _normalized(_cross(helper, d))
        y = _cross([-c for c in d], x)
        z = [-c for c in d]
        matrix = [[x[r], y[r], z[r], 0.0] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
        return {"type": "SUN", "color": light["color"], "energy": light["intensity"],
                "matrix": matrix}
    p = light["position"]
    if light["type"] == "spot":
        out = {"type": "SPOT", "color": light["color"],
               "energy": light["intensity"] * units.spot_watts_per_intensity,
               "matrix": _aim_matrix(light["direction"], p),
               "spot_size": math.radians(light["spot_size_deg"]),
               "spot_blend": light["spot_blend"]}
        if light.get("axis_cosine", True) != units.spot_axis_cosine:
            out["mask"] = (f"its cone {'holds' if light.get('axis_cosine', True) else 'lacks'} "
                           f"the extra cosine off the axis that Blender {units.name}'s spot "
                           f"{'lacks' if light.get('axis_cosine', True) else 'holds'}: "
                           "it is right on the axis only")
        return out
    if light["type"] == "area":
        width, height = area_sides(light)
        return {"type": "AREA", "color": light["color"],
                "energy": light["intensity"] * units.area_watts_per_intensity,
                "matrix": _aim_matrix(light["direction"], p, light["x_axis"]),
                "shape": light["shape"].upper(), "size": width, "size_y": height}
    matrix = [[1.0, 0.0, 0.0, p[0]], [0.0, 1.0, 0.0, p[1]], [0.0, 0.0, 1.0, p[2]],
              [0.0, 0.0, 0.0, 1.0]]
    return {"type": "POINT", "color": light["color"],
            "energy": light["intensity"] * units.point_watts_per_irradiance, "matrix": matrix}
