#!/usr/bin/env python3
"""Writes the scene variants issue 15 renders from one material: the paper
scene as it is, with its key light grazing the cloth and its point light on
the other side, with a grazing camera, and with the camera 4 x farther away
(about 1.75 pixels per weave repeat). Each variant is the paper scene.json
with a few fields changed; mesh and cloth paths become absolute, so the
files can live anywhere.

usage: variants.py SCENE.json OUT_DIR
"""
import json
import math
import os
import sys

import numpy as np


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                faces.append([int(p.split("/")[0]) - 1 for p in parts[1:]])
    return np.array(verts), faces


def mean_plane(verts, faces):
    """Area-weighted mean normal and centroid of the mesh."""
    n_sum, c_sum, a_sum = np.zeros(3), np.zeros(3), 0.0
    for f in faces:
        p = verts[f]
        n = np.zeros(3)
        for i in range(len(f)):  # Newell's normal
            n += np.cross(p[i], p[(i + 1) % len(f)])
        area = 0.5 * np.linalg.norm(n)
        n_sum += 0.5 * n
        c_sum += area * p.mean(axis=0)
        a_sum += area
    return n_sum / np.linalg.norm(n_sum), c_sum / a_sum


def unit(v):
    return v / np.linalg.norm(v)


def main():
    scene_path, out_dir = sys.argv[1], sys.argv[2]
    base_dir = os.path.dirname(os.path.abspath(scene_path))
    with open(scene_path) as f:
        scene = json.load(f)
    for obj in scene["objects"]:
        for key in ("mesh", "cloth"):
            if isinstance(obj.get(key), str):
                obj[key] = os.path.join(base_dir, obj[key])
    verts, faces = read_obj(scene["objects"][0]["mesh"])
    normal, centre = mean_plane(verts, faces)
    os.makedirs(out_dir, exist_ok=True)

    def write(name, s):
        with open(os.path.join(out_dir, name + ".json"), "w") as f:
            json.dump(s, f, indent=2)

    write("paper", scene)

    # (b) The key light 15 degrees above the mean plane, from its own azimuth
    # in that plane; the point light mirrored to the other side of the cloth
    # (across the plane through the centre spanned by the normal and y).
    s = json.loads(json.dumps(scene))
    key = next(l for l in s["lights"] if l["type"] == "directional")
    to_light = -unit(np.array(key["direction"], float))
    along = unit(to_light - normal * to_light.dot(normal))
    elev = math.radians(15.0)
    to_light = math.cos(elev) * along + math.sin(elev) * normal
    key["direction"] = list(-to_light)
    point = next(l for l in s["lights"] if l["type"] == "point")
    p = np.array(point["position"], float)
    side = unit(np.cross(normal, [0.0, 1.0, 0.0]))
    point["position"] = list(p - 2.0 * side * (p - centre).dot(side))
    write("grazing_light", s)

    # (c) The camera at 12 degrees above the mean plane, same distance and
    # target, from the azimuth it has now.
    s = json.loads(json.dumps(scene))
    cam = s["camera"]
    pos, look = np.array(cam["position"], float), np.array(cam["look_at"], float)
    dist = np.linalg.norm(pos - look)
    to_cam = unit(pos - look)
    along = unit(to_cam - normal * to_cam.dot(normal))
    elev = math.radians(12.0)
    cam["position"] = list(look + dist * (math.cos(elev) * along + math.sin(elev) * normal))
    write("grazing_camera", s)

    # (c) The camera 4 x farther from its target: about 1.75 px per repeat.
    s = json.loads(json.dumps(scene))
    cam = s["camera"]
    cam["position"] = list(look + 4.0 * (pos - look))
    write("far_camera", s)


if __name__ == "__main__":
    main()
