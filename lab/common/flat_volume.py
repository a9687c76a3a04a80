"""Where the volume texture of a flat clothbake scene lies in world space.

Plain Python (json only): imported by lab/common/tile_volume.py (/usr/bin/python3)
and by lab/common/volume_render.py (inside Blender).

For a scene whose first object is one flat, regular UV patch (testscenes/flat:
a square of quads with UVs spanning a whole number of repeats), clothbake maps
texture point (x, y, z) mm to world

    P = O + (x / mm_per_u) U + (y / mm_per_v) V + (z - thickness_mm) w N

where O is the world position of UV (u0, v0) (the smallest UV), U and V the
world vectors of one UV unit along u and v, mm_per_u = repeats_per_uv x
repeat_mm (mm of texture per UV unit), N the unit front normal and
w = thickness_world / thickness_mm (world per texture mm through the cloth;
docs/formats/scene.md "Choosing thickness_world"). The volume lies behind
the surface (z = thickness_mm is the surface).
"""
import json
import math
import os


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _norm(a):
    return math.sqrt(sum(x * x for x in a))


def read_obj(path):
    """Vertices, UVs and faces ((pos index, uv index) per corner, 0-based)."""
    v, vt, faces = [], [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w or w[0].startswith("#"):
                continue
            if w[0] == "v":
                v.append([float(x) for x in w[1:4]])
            elif w[0] == "vt":
                vt.append([float(x) for x in w[1:3]])
            elif w[0] == "f":
                corners = []
                for c in w[1:]:
                    p = c.split("/")
                    corners.append((int(p[0]) - 1, int(p[1]) - 1))
                faces.append(corners)
    return v, vt, faces


def layout(scene_path, size_mm):
    """The world placement of the first object's volume texture.

    size_mm: [x, y, z] of one repeat (volume.json's size_mm). Returns a dict:
    origin, u_vec, v_vec (world vectors of one UV unit), normal (unit),
    repeats [nu, nv] (whole repeats across the patch), world_per_mm [along x,
    along y, through z], thickness_world, extinction_per_world (extinction_per_mm
    times the world-to-mm scale along the cloth), albedo, camera, lights,
    background.
    """
    with open(scene_path) as f:
        scene = json.load(f)
    obj = scene["objects"][0]
    mesh = os.path.join(os.path.dirname(os.path.abspath(scene_path)), obj["mesh"])
    v, vt, faces = read_obj(mesh)
    pairs = {(p, t) for face in faces for (p, t) in face}
    uvs = [vt[t] for _, t in pairs]
    u0, v0 = min(u for u, _ in uvs), min(w for _, w in uvs)
    u1, v1 = max(u for u, _ in uvs), max(w for _, w in uvs)

    def at(u, w):
        for p, t in pairs:
            if abs(vt[t][0] - u) < 1e-6 and abs(vt[t][1] - w) < 1e-6:
                return v[p]
        raise ValueError("%s: no vertex at UV (%g, %g); need a flat regular patch" % (mesh, u, w))

    o, pu, pv = at(u0, v0), at(u1, v0), at(u0, v1)
    u_vec = [x / (u1 - u0) for x in _sub(pu, o)]
    v_vec = [x / (v1 - v0) for x in _sub(pv, o)]
    n = _cross(u_vec, v_vec)
    normal = [x / _norm(n) for x in n]
    for p, _ in pairs:  # flatness
        if abs(sum(a * b for a, b in zip(_sub(v[p], o), normal))) > 1e-6 * _norm(u_vec):
            raise ValueError("%s: vertex %d is off the plane; need a flat patch" % (mesh, p))
    rpu = obj.get("repeats_per_uv", 40)
    nu, nv = rpu * (u1 - u0), rpu * (v1 - v0)
    if abs(nu - round(nu)) > 1e-6 or abs(nv - round(nv)) > 1e-6:
        raise ValueError("the patch spans %g x %g repeats; need whole repeats" % (nu, nv))
    mm_per_u, mm_per_v = rpu * size_mm[0], rpu * size_mm[1]
    thickness_world = obj.get("thickness_world", 0.01)
    wpm = [_norm(u_vec) / mm_per_u, _norm(v_vec) / mm_per_v, thickness_world / size_mm[2]]
    return {
        "origin": o,
        "u_vec": u_vec,
        "v_vec": v_vec,
        "normal": normal,
        "repeats": [int(round(nu)), int(round(nv))],
        "world_per_mm": wpm,
        "thickness_world": thickness_world,
        # Texture path length in mm per world unit is 1 / world_per_mm; the
        # map is isotropic for this scene (checked by the caller if needed).
        "extinction_per_world": obj.get("extinction_per_mm", 40) / wpm[0],
        "albedo": obj.get("isotropic_albedo", [0.8, 0.8, 0.8]),
        "camera": scene["camera"],
        "lights": scene["lights"],
        "background": scene.get("background", [0, 0, 0]),
        "shading": scene.get("render", {}).get("shading", "fiber"),
    }
