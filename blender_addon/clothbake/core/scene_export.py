"""Export: a clothbake scene (docs/formats/scene.md) built from plain data
(world matrices, lens and sensor, light energies, quad meshes), the inverse
of clothbake.core.scene's blender_camera / blender_light, and written to
disk atomically. Whether a scene file still describes a Blender scene is
scene_match.py's.

Blender keeps floats as float32, so numbers that went through it come back
a few ulps off ("0.7" as 0.699999988). Where the scene the Blender scene was
imported from (the *hint*) says the same thing within SNAP_TOLERANCE, the
hint's own numbers are written, so exporting an unchanged scene gives the
numbers it was imported with (and the same scene hash for its lookup).
"""
import json
import math
import os
import re
import struct

from . import defaults
from .cloth_fields import short_float
from .errors import ClothbakeError
from .obj import QuadMeshData, format_obj
from .light_units import BLENDER_3
from .scene import (FIBER_MODELS,  # noqa: F401 (for the panel)
                    SHADINGS,
                    TRANSMITTANCES, camera_basis)

RENDER_DEFAULTS = defaults.RENDER_DEFAULTS  # the program's (core/defaults.py)
OBJECT_KEYS = ("repeats_per_uv", "thickness_world", "extinction_per_mm")

# Relative tolerance under which a number is taken to be the hint's number
# back from float32 (float32 has 24 bits: relative steps of 6e-8).
SNAP_TOLERANCE = 1e-6


# Small vector helpers (lists of 3 floats).
def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _norm(a):
    return math.sqrt(sum(c * c for c in a))


def normalized(a):
    n = _norm(a)
    return [c / n for c in a] if n > 0 else [0.0, 0.0, 0.0]


def is_close(a, b, tol=SNAP_TOLERANCE):
    """Numbers or vectors equal within tol relative to their size (at least 1)."""
    if isinstance(a, (int, float)):
        return abs(a - b) <= tol * max(1.0, abs(a), abs(b))
    return len(a) == len(b) and _norm(_sub(a, b)) <= tol * max(1.0, _norm(a), _norm(b))


def _column(matrix, c):
    return [float(matrix[r][c]) for r in range(3)]


def _snap(value, hint):
    """hint when value is hint back from float32, else value (float32 tidied)."""
    if hint is not None and is_close(value, hint):
        return list(hint) if isinstance(hint, list) else hint
    if isinstance(value, (int, float)):
        return short_float(value)
    return [short_float(c) for c in value]


def camera_from_blender(matrix, lens, sensor_width, sensor_height, sensor_fit, resolution,
                        hint=None, look_distance=1.0):
    """The clothbake camera of a Blender perspective camera.

    matrix: its 4x4 world matrix (rows; the camera looks along local -Z, +Y
    up); lens, sensor_width, sensor_height in mm; sensor_fit "AUTO",
    "HORIZONTAL" or "VERTICAL"; resolution [width, height] in pixels. The
    field of view is the one Blender renders: AUTO fits sensor_width to the
    larger image side. look_at is a point straight ahead, at the hint's
    distance if there is a hint, else `look_distance`; up is the camera's
    own up unless the hint's up gives the same image.
    """
    width, height = int(resolution[0]), int(resolution[1])
    if sensor_fit == "AUTO":
        axis, sensor = ("horizontal" if width >= height else "vertical"), sensor_width
    elif sensor_fit == "HORIZONTAL":
        axis, sensor = "horizontal", sensor_width
    elif sensor_fit == "VERTICAL":
        axis, sensor = "vertical", sensor_height
    else:
        raise ClothbakeError(f"unknown sensor fit '{sensor_fit}'", "", "camera")
    if not lens > 0 or not sensor > 0:
        raise ClothbakeError("lens and sensor size must be greater than 0", "", "camera")
    fov_deg = math.degrees(2.0 * math.atan(0.5 * sensor / lens))

    position = _column(matrix, 3)
    forward = normalized([-c for c in _column(matrix, 2)])
    up = normalized(_column(matrix, 1))
    if _norm(forward) == 0 or _norm(up) == 0:
        raise ClothbakeError("the camera's world matrix is singular", "", "camera")

    if hint is not None and hint.get("fov_axis") == axis:
        fov_deg = _snap(fov_deg, hint["fov_deg"])
    else:
        fov_deg = short_float(fov_deg)
    look_at = None
    if hint is not None:
        hint_offset = _sub(hint["look_at"], hint["position"])
        if is_close(position, hint["position"]) and is_close(forward, normalized(hint_offset)):
            position, look_at = list(hint["position"]), list(hint["look_at"])
        else:
            look_distance = _norm(hint_offset) or look_distance
    if look_at is None:
        position = [short_float(c) for c in position]
        look_at = [p + look_distance * f for p, f in zip(position, forward)]
    camera = {"position": position, "look_at": look_at, "up": up, "fov_deg": fov_deg,
              "fov_axis": axis, "resolution": [width, height]}
    if hint is not None:
        try:
            _, hint_up, _ = camera_basis(dict(camera, up=hint["up"]))
            if is_close(hint_up, up):
                camera["up"] = list(hint["up"])
        except (ZeroDivisionError, ValueError):
            pass
    return camera


_LIGHT_TYPES = {"SUN": "directional", "POINT": "point", "SPOT": "spot", "AREA": "area"}
# Relative tolerance of a light's scale and axes: a spot's X and Y scale
# equal, an area light's axes orthogonal (float32 matrices, rotations).
SCALE_TOLERANCE = 1e-4


def _snap_direction(direction, hint_direction):
    if hint_direction is not None and is_close(direction, normalized(hint_direction)):
        return list(hint_direction)
    return direction


def _f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def _degrees(radians):
    """A float32 angle in radians as the shortest number of degrees that
    gives it back (Blender shows and stores 50 degrees as float32 radians:
    50.00000025 degrees read back)."""
    degrees = math.degrees(radians)
    if _f32(radians) == radians:
        for digits in range(6, 10):
            d = float(f"%.{digits}g" % degrees)
            if _f32(math.radians(d)) == radians:
                return d
    return degrees


def _unit_scale(length):
    """A rotation column's length: 1 when it is 1 to float32 rounding (a
    light rotated, not scaled), so its sizes are written as Blender shows them."""
    return 1.0 if abs(length - 1.0) <= 4e-7 else length


def _spot_from_blender(name, matrix, energy, settings, hint, units):
    where = f"light '{name}'"
    sx, sy = _norm(_column(matrix, 0)), _norm(_column(matrix, 1))
    if abs(sx - sy) > SCALE_TOLERANCE * max(sx, sy):
        raise ClothbakeError(f"scale: its X and Y scale differ ({sx:.4g}, {sy:.4g}): "
                             "Eevee draws that cone as an ellipse, and "
                             "clothbake's spot cone is round (Cycles 3.4 ignores a spot's "
                             "scale); make them equal", "", where)
    direction = normalized([-c for c in _column(matrix, 2)])
    if _norm(direction) == 0:
        raise ClothbakeError("the light's world matrix is singular", "", where)
    size_deg = _degrees(float(settings["spot_size"]))
    blend = float(settings["spot_blend"])
    light = {"type": "spot",
             "position": _snap(_column(matrix, 3), hint["position"] if hint else None),
             "direction": _snap_direction(direction, hint["direction"] if hint else None),
             "spot_size_deg": _snap(size_deg, hint["spot_size_deg"] if hint else None),
             "spot_blend": _snap(blend, hint["spot_blend"] if hint else None),
             "intensity": float(energy) / units.spot_watts_per_intensity}
    if not units.spot_axis_cosine:
        light["axis_cosine"] = False
    return light


def _area_from_blender(name, matrix, energy, settings, hint, units):
    where = f"light '{name}'"
    spread = float(settings.get("spread", math.pi))
    if abs(spread - math.pi) > 1e-5:
        raise ClothbakeError(f"spread: {math.degrees(spread):.4g} degrees; clothbake's "
                             "area lights emit into the whole half-space in front of them "
                             "(Spread 180 degrees)", "", where)
    x, y, z = (_column(matrix, c) for c in range(3))
    sx, sy, sz = (_unit_scale(_norm(c)) for c in (x, y, z))
    if not (sx > 0 and sy > 0 and sz > 0):
        raise ClothbakeError("the light's world matrix is singular", "", where)
    dots = (sum(a * b for a, b in zip(x, y)) / (sx * sy), sum(a * b for a, b in zip(x, z)) /
            (sx * sz), sum(a * b for a, b in zip(y, z)) / (sy * sz))
    if max(abs(d) for d in dots) > SCALE_TOLERANCE:
        raise ClothbakeError("its world matrix is sheared (a parent scaled unevenly and a "
                             "rotation between): its shape is a parallelogram, which clothbake "
                             "cannot model", "", where)
    shape = str(settings.get("shape", "SQUARE")).lower()
    size, size_y = (short_float(settings[k]) for k in ("size", "size_y" if "size_y" in settings
                                                        else "size"))
    if shape in ("square", "disk"):
        width, height = size * sx, size * sy
        if abs(width - height) > SCALE_TOLERANCE * max(width, height):
            shape = "rectangle" if shape == "square" else "ellipse"   # scaled unevenly
    elif shape in ("rectangle", "ellipse"):
        width, height = size * sx, size_y * sy
    else:
        raise ClothbakeError(f"shape: unknown area shape '{shape}'", "", where)
    hint_size = hint["size"] if hint and hint.get("shape") == shape else None
    if shape in ("square", "disk"):
        out_size = _snap(width, hint_size if isinstance(hint_size, float) else None)
    else:
        out_size = _snap([width, height], hint_size if isinstance(hint_size, list) else None)
    return {"type": "area",
            "position": _snap(_column(matrix, 3), hint["position"] if hint else None),
            "direction": _snap_direction(normalized([-c for c in z]),
                                         hint["direction"] if hint else None),
            "x_axis": _snap_direction(normalized(x), hint["x_axis"] if hint else None),
            "shape": shape, "size": out_size,
            "intensity": float(energy) / units.area_watts_per_intensity}


def light_from_blender(name, light_type, matrix, color, energy, hint=None, settings=None,
                       units=BLENDER_3, unsupported=None):
    """The clothbake light of a Blender light, its watts read in `units`
    (light_units.py: the Blender version's): SUN -> directional (travelling
    along the light's -Z, irradiance = strength), POINT -> point (irradiance
    at distance 1 = watts / 4 pi), SPOT -> spot (the same, masked by the
    cone: `settings` spot_size in radians, spot_blend; axis_cosine false
    from Blender 4.0), AREA -> area (`settings` shape, size, size_y, spread;
    the sides are the sizes times the matrix's scale along X and Y; radiant
    intensity along its normal = watts / units.area_watts_per_intensity).
    `energy` is the watts with Exposure applied (light_units.effective_watts).
    A light radius (point, spot) is not in clothbake's lights and is
    ignored. What clothbake cannot model (other types, an area spread other
    than 180 degrees, a spot whose X and Y scale differ, a sheared area
    light, `unsupported`: light_units.unsupported_light_setting's reason) is
    refused, naming the light and the setting."""
    kind = _LIGHT_TYPES.get(light_type)
    if kind is None:
        raise ClothbakeError(f"{light_type.lower()} lights are not supported; clothbake has "
                             "sun (directional), point, spot and area lights", "",
                             f"light '{name}'")
    if unsupported is not None:
        raise ClothbakeError(unsupported, "", f"light '{name}'")
    if hint is not None and hint.get("type") != kind:
        hint = None
    color = _snap([float(c) for c in color], hint["color"] if hint else None)
    if light_type == "SUN":
        direction = normalized([-c for c in _column(matrix, 2)])
        if _norm(direction) == 0:
            raise ClothbakeError("the light's world matrix is singular", "", f"light '{name}'")
        if hint is not None and is_close(direction, normalized(hint["direction"])):
            direction = list(hint["direction"])
        intensity = _snap(float(energy), hint["intensity"] if hint else None)
        return {"type": "directional", "direction": direction, "color": color,
                "intensity": intensity}
    if light_type == "POINT":
        position = _snap(_column(matrix, 3), hint["position"] if hint else None)
        intensity = float(energy) / units.point_watts_per_irradiance
        if hint is not None and is_close(intensity, hint["intensity"]):
            intensity = hint["intensity"]
        return {"type": "point", "position": position, "color": color, "intensity": intensity}
    if settings is None:
        raise ClothbakeError(f"the {kind} light's settings are missing", "", f"light '{name}'")
    light = (_spot_from_blender if light_type == "SPOT" else _area_from_blender)(
        name, matrix, energy, settings, hint, units)
    if hint is not None and is_close(light["intensity"], hint["intensity"]):
        light["intensity"] = hint["intensity"]
    light["color"] = color
    return light


def quad_mesh(name, positions, faces, face_uvs):
    """QuadMeshData of a mesh given as positions (world), faces (vertex
    indices per face, in corner order) and face_uvs (per face, one (u, v)
    per corner; None when the mesh has no UV map). Faces and corners keep
    their order (face q is the lookup's quad q). Raises ClothbakeError
    naming the object and the first face that is not a quad."""
    where = f"object '{name}'"
    bad = [i for i, f in enumerate(faces) if len(f) != 4]
    if bad:
        more = f" ({len(bad)} of {len(faces)} faces are not quads)" if len(bad) > 1 else ""
        raise ClothbakeError(f"face {bad[0]} has {len(faces[bad[0]])} corners{more}; clothbake "
                             "needs quads (4 corners)", "", where)
    if not faces:
        raise ClothbakeError("the mesh has no faces", "", where)
    if face_uvs is None:
        raise ClothbakeError("the mesh has no UV map; the weave follows the UVs", "", where)
    mesh = QuadMeshData(positions=[tuple(float(c) for c in p) for p in positions])
    uv_index = {}
    for face, uvs in zip(faces, face_uvs):
        ts = []
        for uv in uvs:
            key = (float(uv[0]), float(uv[1]))
            if key not in uv_index:
                uv_index[key] = len(mesh.uvs)
                mesh.uvs.append(key)
            ts.append(uv_index[key])
        mesh.quads.append((tuple(int(p) for p in face), tuple(ts)))
    return mesh


def render_settings(values=None):
    """The scene's `render` block: RENDER_DEFAULTS with `values` over them."""
    render = dict(RENDER_DEFAULTS)
    for key, value in (values or {}).items():
        if key not in RENDER_DEFAULTS:
            raise ClothbakeError(f"unknown render setting '{key}'", "", "render")
        render[key] = value
    for key in ("step_cells", "cutoff"):
        render[key] = short_float(render[key])
    for key in ("spp", "fiber_samples", "seed"):
        render[key] = int(render[key])
    return render


def build_scene(camera, lights, objects, background, render=None, name=None, description=None):
    """The scene model export writes: camera and lights as clothbake dicts
    (camera_from_blender, light_from_blender), objects as dicts with name,
    mesh (QuadMeshData, world space), cloth (absolute path of a spec file, or
    a spec dict), repeats_per_uv, thickness_world, extinction_per_mm and
    optionally isotropic_albedo and volume (path of a VDB whose texture
    replaces the generated one); background linear RGB."""
    if not lights:
        raise ClothbakeError("a clothbake scene needs at least one light (sun, point, spot or "
                             "area)", "", "lights")
    if not objects:
        raise ClothbakeError("a clothbake scene needs at least one cloth object", "", "objects")
    out_objects = []
    for o in objects:
        cloth = o["cloth"]
        if isinstance(cloth, str):
            cloth = os.path.abspath(cloth)
        elif not isinstance(cloth, dict):
            raise ClothbakeError("cloth must be a spec dict or the path of a spec file", "",
                                 f"object '{o['name']}'")
        entry = {"name": o["name"], "mesh": o["mesh"], "cloth": cloth}
        for key in OBJECT_KEYS:
            entry[key] = short_float(o[key])
        if o.get("isotropic_albedo") is not None:
            entry["isotropic_albedo"] = [short_float(c) for c in o["isotropic_albedo"]]
        if o.get("volume"):
            entry["volume"] = os.path.abspath(o["volume"])
        out_objects.append(entry)
    model = {"camera": camera, "lights": lights, "objects": out_objects,
             "background": [short_float(c) for c in background],
             "render": render_settings(render)}
    if name:
        model["name"] = name
    if description:
        model["description"] = description
    return model


def mesh_filenames(model):
    """One OBJ file name per object, from its name, unique within the scene."""
    names, used = [], set()
    for o in model["objects"]:
        stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", o["name"]).strip("._") or "object"
        candidate, n = f"{stem}.obj", 1
        while candidate.lower() in used:
            n += 1
            candidate = f"{stem}_{n}.obj"
        used.add(candidate.lower())
        names.append(candidate)
    return names


def scene_json(model, scene_path):
    """The JSON dict of `model` for a scene file at `scene_path`: meshes,
    cloth spec files and VDBs referred to relative to its folder."""
    folder = os.path.dirname(os.path.abspath(scene_path))
    root = {}
    for key in ("name", "description"):
        if key in model:
            root[key] = model[key]
    root["camera"] = model["camera"]
    root["lights"] = model["lights"]
    objects = []
    for o, filename in zip(model["objects"], mesh_filenames(model)):
        entry = dict(o)
        entry["mesh"] = filename
        for key in ("cloth", "volume"):
            if isinstance(o.get(key), str):
                try:
                    entry[key] = os.path.relpath(o[key], folder)
                except ValueError:  # another drive
                    entry[key] = o[key]
        objects.append(entry)
    root["objects"] = objects
    root["background"] = model["background"]
    root["render"] = model["render"]
    return root


def _write_atomic(path, text):
    tmp = f"{path}.tmp-{os.getpid()}"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise ClothbakeError(f"cannot write: {e.strerror}", path) from None


def write_scene(model, scene_path):
    """Writes the scene file and one OBJ per object beside it (an existing
    OBJ of the same name is replaced). Each file goes to a temporary name and
    is renamed into place, meshes first, so the scene file never refers to a
    missing or half-written mesh. Returns the absolute scene path."""
    scene_path = os.path.abspath(scene_path)
    folder = os.path.dirname(scene_path)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise ClothbakeError(f"cannot create the folder: {e.strerror}", folder) from None
    for o, filename in zip(model["objects"], mesh_filenames(model)):
        _write_atomic(os.path.join(folder, filename),
                      format_obj(o["mesh"], f"clothbake object '{o['name']}', written by the "
                                             "clothbake Blender add-on"))
    _write_atomic(scene_path, json.dumps(scene_json(model, scene_path), indent=2) + "\n")
    return scene_path
