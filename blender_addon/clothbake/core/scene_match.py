"""Whether a scene file still describes a Blender scene (its model, as
clothbake.core.scene_export builds it): the same camera image, lights,
objects, meshes within a tolerance, cloth, background and render settings.
A bake reads the scene file as it is when it does, and exports one first
when it does not."""
import json
import os

from .errors import ClothbakeError
from .obj import read_obj
from .scene import camera_basis, load_scene
from .scene_export import OBJECT_KEYS, SNAP_TOLERANCE, is_close, normalized, render_settings


def _same_cloth(a, b):
    def as_dict(c):
        if isinstance(c, dict):
            return c
        try:
            with open(c, encoding="utf-8") as f:
                return json.load(f)
        except (OSError, ValueError):
            return None
    if isinstance(a, str) and isinstance(b, str) and os.path.abspath(a) == os.path.abspath(b):
        return True
    da, db = as_dict(a), as_dict(b)
    return da is not None and da == db


def _same_mesh(a, b, tol):
    if len(a.quads) != len(b.quads):
        return False
    for (pa, ta), (pb, tb) in zip(a.quads, b.quads):
        for i in range(4):
            if not is_close(list(a.positions[pa[i]]), list(b.positions[pb[i]]), tol):
                return False
            if not is_close(list(a.uvs[ta[i]]), list(b.uvs[tb[i]]), tol):
                return False
    return True


def _same_light(a, b, tol):
    if a["type"] != b["type"] or not is_close(a["color"], b["color"], tol) or \
            not is_close(a["intensity"], b["intensity"], tol):
        return False
    if a["type"] == "directional":
        return is_close(normalized(a["direction"]), normalized(b["direction"]), tol)
    if not is_close(a["position"], b["position"], tol):
        return False
    if a["type"] == "point":
        return True
    if not is_close(normalized(a["direction"]), normalized(b["direction"]), tol):
        return False
    if a["type"] == "spot":
        return is_close(a["spot_size_deg"], b["spot_size_deg"], tol) and \
            is_close(a["spot_blend"], b["spot_blend"], tol) and \
            a.get("axis_cosine", True) == b.get("axis_cosine", True)
    return (a["shape"] == b["shape"] and is_close(normalized(a["x_axis"]),
                                                normalized(b["x_axis"]), tol)
            and type(a["size"]) is type(b["size"]) and is_close(a["size"], b["size"], tol))


def same_camera(a, b, tol=SNAP_TOLERANCE):
    """Whether two clothbake cameras give the same image."""
    if a["fov_axis"] != b["fov_axis"] or list(a["resolution"]) != list(b["resolution"]):
        return False
    if not is_close(a["fov_deg"], b["fov_deg"], tol) or not is_close(a["position"], b["position"], tol):
        return False
    return all(is_close(x, y, tol) for x, y in zip(camera_basis(a), camera_basis(b)))


def scene_matches_file(model, path, tol=SNAP_TOLERANCE):
    """Whether the scene file at `path` describes `model` (same camera image,
    lights, objects, meshes within tol, cloth, background and render
    settings), so baking that file is baking this scene. False when the file
    cannot be read."""
    try:
        other = load_scene(path)
        other_meshes = [read_obj(o["mesh_path"]) for o in other["objects"]]
    except ClothbakeError:
        return False
    if not same_camera(model["camera"], other["camera"], tol):
        return False
    if len(model["lights"]) != len(other["lights"]) or not all(
            _same_light(a, b, tol) for a, b in zip(model["lights"], other["lights"])):
        return False
    if len(model["objects"]) != len(other["objects"]):
        return False
    for o, p, mesh in zip(model["objects"], other["objects"], other_meshes):
        if o["name"] != p["name"] or not all(is_close(o[k], p[k], tol) for k in OBJECT_KEYS):
            return False
        albedo = o.get("isotropic_albedo") or [0.8, 0.8, 0.8]
        if not is_close(albedo, p["isotropic_albedo"], tol):
            return False
        if not _same_cloth(o["cloth"], p.get("cloth_path", p.get("cloth"))):
            return False
        volume = os.path.abspath(o["volume"]) if o.get("volume") else None
        if volume != p.get("volume_path"):
            return False
        if not _same_mesh(o["mesh"], mesh, tol):
            return False
    if not is_close(model["background"], other["background"], tol):
        return False
    try:
        other_render = render_settings(other["json"].get("render") or {})
    except ClothbakeError:
        return False
    return all(is_close(v, other_render[k], tol) if isinstance(v, float) else v == other_render[k]
               for k, v in model["render"].items())
