"""Renders the Blender figures of the cloth material (issue 16), inside
Blender (run by blender_measure.py):

    blender -b --factory-startup --python-exit-code 1 -P blender_frames.py -- \
        MODE SCENE.json MATERIAL_DIR OUT_PREFIX [--samples N] [--engine E]
        [--route R] [--target OBJ] [--value V] [--frames F] [--timings T.json]

MODE
  still   one frame (the headless route, plus the frame's timings)
  anim    a shape key toward --target's vertices (value 0 at frame 1, --value
          at frame 2), the material applied once at frame 1; frames 1 and 2
  strip   the key light (the scene's first light, a sun) circles the cloth
          about the scene's up axis: --frames frames, one full turn,
          keyframed on the light's rotation; the material applied once
  sphere  the cycles-lit route with a sphere between the key light and the
          cloth (hidden from the camera), and the exact route beside it
Every frame is written as OUT_PREFIX_<name>.exr (linear) and .png.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon"))
import addon_utils  # noqa: E402

addon_utils.enable("clothbake", default_set=True, handle_error=None)
from clothbake.blender.headless import bilinear_patches
    from clothbake.blender.render_engines import use_eevee  # noqa: E402
from clothbake.blender.material_apply import apply_material  # noqa: E402
from clothbake.blender.scene_import import import_scene  # noqa: E402


def save(scene, prefix, name, timings):
    start = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    timings[name] = time.perf_counter() - start
    image = bpy.data.images["Render Result"]
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth = "OPEN_EXR", "32"
    image.save_render(f"{prefix}_{name}.exr", scene=scene)
    settings.file_format, settings.color_depth = "PNG", "8"
    image.save_render(f"{prefix}_{name}.png", scene=scene)
    settings.file_format, settings.color_depth = "OPEN_EXR", "32"


def read_obj_positions(path):
    out = []
    with open(path) as f:
        for line in f:
            p = line.split()
            if p and p[0] == "v":
                out.append(tuple(float(x) for x in p[1:4]))
    return out


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=("still", "anim", "strip", "sphere"))
    ap.add_argument("scene")
    ap.add_argument("material")
    ap.add_argument("prefix")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--engine", choices=("cycles", "eevee"), default="cycles")
    ap.add_argument("--route", choices=("exact", "cycles-lit"), default="exact")
    ap.add_argument("--target")
    ap.add_argument("--value", type=float, default=1.0)
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--timings")
    args = ap.parse_args(argv)

    timings = {}
    (obj,) = import_scene(args.scene, clear=True, samples=args.samples)
    scene = bpy.context.scene
    if args.engine == "eevee":
        use_eevee(scene, args.samples)
    bilinear_patches(obj)
    start = time.perf_counter()
    apply_material(obj, args.material, route=args.route, scene=scene)
    timings["apply_seconds"] = time.perf_counter() - start
    lights = sorted((o for o in scene.objects if o.type == "LIGHT"), key=lambda o: o.name)

    if args.mode == "still":
        save(scene, args.prefix, "still", timings)
    elif args.mode == "anim":
        obj.shape_key_add(name="Basis")
        key = obj.shape_key_add(name="toward flat")
        for i, co in enumerate(read_obj_positions(args.target)):
            key.data[i].co = co
        key.value = 0.0
        key.keyframe_insert("value", frame=1)
        key.value = args.value
        key.keyframe_insert("value", frame=2)
        for frame in (1, 2):
            scene.frame_set(frame)
            save(scene, args.prefix, f"frame{frame}", timings)
    elif args.mode == "strip":
        sun = lights[0]
        sun.rotation_mode = "XYZ"
        base = sun.matrix_world.copy()
        up = Vector(json.load(open(args.scene))["camera"]["up"]).normalized()
        for f in range(args.frames):
            turn = Matrix.Rotation(2.0 * math.pi * f / args.frames, 4, up)
            sun.matrix_world = turn @ base
            sun.keyframe_insert("rotation_euler", frame=f + 1)
        for f in range(args.frames):
            scene.frame_set(f + 1)
            save(scene, args.prefix, f"turn{f}", timings)
    elif args.mode == "sphere":
        sun = lights[0]
        to_sun = (sun.matrix_world.to_3x3() @ Vector((0, 0, 1))).normalized()
        centre = Vector(obj.matrix_world.translation)
        me = obj.data
        centre = sum((obj.matrix_world @ v.co for v in me.vertices), Vector()) / len(me.vertices)
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.35, location=centre + 1.2 * to_sun,
                                             segments=48, ring_count=24)
        sphere = bpy.context.active_object
        sphere.visible_camera = False
        save(scene, args.prefix, f"sphere_{args.route}", timings)
    timings["samples"] = args.samples
    timings["engine"] = args.engine
    timings["route"] = args.route
    if args.timings:
        with open(args.timings, "w") as f:
            json.dump(timings, f, indent=2)
    print(json.dumps(timings))


main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
