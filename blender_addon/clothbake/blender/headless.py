"""The headless comparison route: import a clothbake scene, apply its
lookup (a per-scene bake) or a cloth material, render and write a linear EXR.

    blender -b --factory-startup --python-exit-code 1 \
        -P blender_addon/headless_render.py -- SCENE.json BAKE_OR_MATERIAL_DIR OUT.exr \
        [--samples N] [--engine cycles|eevee] [--route exact|cycles-lit] [--seed S]
        [--threads N] [--png OUT.png] [--timings T.json]

A material folder (manifest format "clothbake-material") is applied with the
scene's own lights (clothbake.blender.material_apply), on the route asked;
--engine eevee renders it with Eevee (samples = its render samples). A bake
folder renders in Cycles only, as before.

Exit 0 on success; on a refused input one line "clothbake: error: ..." on
stderr and exit 2, with nothing written under OUT.
"""
import argparse
import json
import os
import sys
import time

import bpy

from ..core.errors import ClothbakeError
from ..core.material_pack import is_material_folder
from .lookup_apply import apply_lookup
from .material_apply import apply_material
from .render_engines import use_eevee
from .scene_import import import_scene


def _write_atomic_render(path, scene):
    """Saves the render result to `path` through a temporary sibling."""
    folder = os.path.dirname(os.path.abspath(path)) or "."
    os.makedirs(folder, exist_ok=True)
    tmp = os.path.join(folder, f".{os.path.basename(path)}.tmp-{os.getpid()}.exr")
    bpy.data.images["Render Result"].save_render(tmp, scene=scene)
    os.replace(tmp, path)


PATCH_LEVELS = 3


def bilinear_patches(obj, levels=PATCH_LEVELS):
    """clothbake's renderer draws each quad as its bilinear patch (the map m);
    Blender draws two flat triangles, whose positions and affine UVs differ
    inside a non-planar quad by a sizeable part of a weave repeat (12% RMSE on
    the paper scene). A Simple subdivision (bilinear, UVs linear) samples the
    patch 2^levels times a side: 3.6% between Blender's and clothbake's
    lookup of the same material at 2 levels (docs/design/material.md)."""
    mod = obj.modifiers.new("clothbake bilinear patches", "SUBSURF")
    mod.subdivision_type = "SIMPLE"
    mod.levels = mod.render_levels = levels
    if hasattr(mod, "uv_smooth"):
        mod.uv_smooth = "NONE"
    return mod


def render_scene(scene_path, bake_dir, out_path, samples=16, seed=1, threads=0, png=None,
                 engine="cycles", route="exact"):
    """Returns the timings of each step in seconds."""
    timings = {}
    material = is_material_folder(bake_dir)
    if engine != "cycles" and not material:
        raise ClothbakeError("a per-scene bake renders in Cycles only (--engine cycles); "
                             "Eevee reads a cloth material", bake_dir)
    start = time.perf_counter()
    objects = import_scene(scene_path, clear=True, samples=samples)
    scene = bpy.context.scene
    scene.cycles.seed = seed
    if threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    if engine == "eevee":
        use_eevee(scene, samples)
    timings["import_seconds"] = time.perf_counter() - start

    start = time.perf_counter()
    notes = []
    for obj in objects:
        if material:
            bilinear_patches(obj)
            _, n = apply_material(obj, bake_dir, route=route, scene=scene)
        else:
            _, n = apply_lookup(obj, bake_dir)
        notes += n
    timings["apply_seconds"] = time.perf_counter() - start

    start = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    timings["render_seconds"] = time.perf_counter() - start

    start = time.perf_counter()
    _write_atomic_render(out_path, scene)
    if png:
        settings = scene.render.image_settings
        settings.file_format, settings.color_depth = "PNG", "8"
        _write_atomic_render(png, scene)
        settings.file_format, settings.color_depth = "OPEN_EXR", "32"
    timings["write_seconds"] = time.perf_counter() - start
    timings["samples"] = samples
    timings["engine"] = engine
    timings["route"] = route if material else "lookup"
    timings["notes"] = notes
    return timings


def main(argv):
    parser = argparse.ArgumentParser(prog="headless_render.py",
                                     description="Render a clothbake scene in Cycles from its lookup")
    parser.add_argument("scene")
    parser.add_argument("bake")
    parser.add_argument("out")
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--engine", choices=("cycles", "eevee"), default="cycles")
    parser.add_argument("--route", choices=("exact", "cycles-lit"), default="exact",
                        help="a material's lighting route (ignored for a bake)")
    parser.add_argument("--png")
    parser.add_argument("--timings", help="write the step timings as JSON here")
    args = parser.parse_args(argv)
    if args.samples < 1:
        parser.error("--samples must be >= 1")
    try:
        timings = render_scene(args.scene, args.bake, args.out, args.samples, args.seed,
                               args.threads, args.png, args.engine, args.route)
    except ClothbakeError as e:
        print(f"clothbake: error: {e}", file=sys.stderr)
        return 2
    text = json.dumps(timings, indent=2)
    if args.timings:
        with open(args.timings + ".tmp", "w") as f:
            f.write(text + "\n")
        os.replace(args.timings + ".tmp", args.timings)
    print(text)
    return 0
