#!/usr/bin/env python3
"""Issue 16's figures: the paper cloth's one default material rendered in
Blender 3.4 (Cycles and Eevee, both routes) against clothbake's converged
references, a two-frame shape-key animation, a sphere's shadow, the README
strip of a circling key light, and render times.

Reads what lab/material_accuracy/measure.py made in out/material (the scene
variants, the 64-spp quarter-step references, material_default) and makes
what is missing the same way. Writes out/material/blender/results.json, the
sheets there, and the pictures the docs show into docs/images/material/.

usage: blender_measure.py [--out out/material] [--exe build/baker/clothbake]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from material_measure import errors, log, run  # noqa: E402

FRAMES = os.path.join(HERE, "blender_frames.py")


def blender(*args):
    cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", FRAMES, "--"]
    start = time.perf_counter()
    p = subprocess.run(cmd + [str(a) for a in args], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd + [str(a) for a in args]) + "\n" + p.stdout[-3000:])
    wall = time.perf_counter() - start
    return wall, json.loads([l for l in p.stdout.splitlines() if l.startswith("{")][-1])


def pixels(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)


def rel(a, b):
    a, b = pixels(a)[..., :3], pixels(b)[..., :3]
    return float(np.sqrt(((a - b) ** 2).mean()) / a.mean())


def reference(exe, scene_path, out, spp=64, quarter=True):
    """clothbake's converged render of a scene (cached by the scene's text)."""
    with open(scene_path) as f:
        s = json.load(f)
    r = s.setdefault("render", {})
    if quarter:
        r.update(step_cells=r.get("step_cells", 0.5) / 4, light_roulette=0.0, seed=7)
    key = json.dumps(s, sort_keys=True)
    if os.path.exists(out) and os.path.exists(out + ".scene.json") and \
            open(out + ".scene.json").read() == key:
        return 0.0
    path = out + ".input.json"
    with open(path, "w") as f:
        f.write(key)
    log(f"reference {os.path.basename(out)} ({spp} spp{', quarter step' if quarter else ''})")
    secs, _, _ = run([exe, "render", path, "-o", out, "--spp", str(spp), "--quiet"])
    with open(out + ".scene.json", "w") as f:
        f.write(key)
    return secs


def png(rgb, path):
    x = np.clip(rgb[..., :3], 0, 1) ** (1 / 2.2)
    buf = oiio.ImageBuf(oiio.ImageSpec(x.shape[1], x.shape[0], 3, oiio.UINT8))
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(x.astype(np.float32)))
    buf.write(path)


def read_obj(path):
    verts, rest = [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if p and p[0] == "v":
                verts.append([float(x) for x in p[1:4]])
            elif not line.startswith("v ") and not line.startswith("#"):
                rest.append(line)
    return np.array(verts), rest


def write_obj(path, verts, rest):
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % tuple(v))
        f.writelines(rest)


def flat_target(verts, n=9):
    """The paper cloth laid flat from its back edge toward the camera: each
    column of the 9 x 9 grid unrolled by arc length (lengths kept)."""
    grid = verts.reshape(n, n, 3)          # [j (v), i (u)]
    out = grid.copy()
    for i in range(n):
        back = grid[n - 1, i]
        arc = 0.0
        for j in range(n - 1, -1, -1):
            if j < n - 1:
                arc += np.linalg.norm(grid[j + 1, i] - grid[j, i])
            out[j, i] = back + np.array([0.0, 0.0, arc])
    return out.reshape(-1, 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "material"))
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "baker", "clothbake"))
    ap.add_argument("--docs", default=os.path.join(ROOT, "docs", "images", "material"))
    args = ap.parse_args()
    exe, out = args.exe, args.out
    scenes = os.path.join(out, "scenes")
    bl = os.path.join(out, "blender")
    os.makedirs(bl, exist_ok=True)
    os.makedirs(args.docs, exist_ok=True)
    if not os.path.isdir(scenes):
        run([sys.executable, os.path.join(HERE, "variants.py"),
             os.path.join(ROOT, "testscenes", "paper", "scene.json"), scenes])
    mat = os.path.join(out, "material_default")
    if not os.path.isfile(os.path.join(mat, "manifest.json")):
        log("material bake (defaults)")
        run([exe, "material", os.path.join(scenes, "paper.json"), "-o", mat, "--quiet"])
    res = {"machine": os.uname().nodename, "cpus": os.cpu_count()}

    # 1. Cycles, exact route, the paper scene and the changed scenes.
    res["cycles_exact"] = {}
    for v in ("paper", "grazing_light", "grazing_camera", "far_camera"):
        ref = os.path.join(out, f"ref_{v}.exr")
        reference(exe, os.path.join(scenes, f"{v}.json"), ref)
        row = {}
        for spp in ((64, 128) if v == "paper" else (64,)):
            prefix = os.path.join(bl, f"{v}_cycles_{spp}")
            wall, t = blender("still", os.path.join(scenes, f"{v}.json"), mat, prefix,
                              "--samples", spp)
            whole, interior = errors(ref, prefix + "_still.exr")
            row[f"{spp}spp"] = {"relative_rmse": whole, "interior_relative_rmse": interior,
                                "render_seconds": t["still"], "wall_seconds": wall}
        res["cycles_exact"][v] = row
        log(f"cycles exact {v}: {json.dumps(row)}")

    # 2. Eevee and the cycles-lit route on the paper scene.
    paper = os.path.join(scenes, "paper.json")
    ref_paper = os.path.join(out, "ref_paper.exr")
    cyc64 = os.path.join(bl, "paper_cycles_64_still.exr")
    prefix = os.path.join(bl, "paper_eevee_64")
    wall, t = blender("still", paper, mat, prefix, "--samples", 64, "--engine", "eevee")
    res["eevee"] = {"vs_reference": errors(ref_paper, prefix + "_still.exr")[0],
                    "vs_cycles_64": rel(cyc64, prefix + "_still.exr"),
                    "render_seconds": t["still"], "wall_seconds": wall}
    # Eevee at the far camera: coarse levels, where GPU filtering of an atlas
    # would bleed tiles (the node tree reads every image Closest).
    prefix = os.path.join(bl, "far_eevee_64")
    blender("still", os.path.join(scenes, "far_camera.json"), mat, prefix, "--samples", 64,
            "--engine", "eevee")
    res["eevee"]["far_camera_vs_reference"] = errors(os.path.join(out, "ref_far_camera.exr"),
                                                     prefix + "_still.exr")[0]
    prefix = os.path.join(bl, "paper_lit_64")
    wall, t = blender("still", paper, mat, prefix, "--samples", 64, "--route", "cycles-lit")
    res["cycles_lit"] = {"vs_exact_64": rel(cyc64, prefix + "_still.exr"),
                         "vs_reference": errors(ref_paper, prefix + "_still.exr")[0],
                         "render_seconds": t["still"]}
    # Noise of the exact route itself at 64 spp: a second seed is the 128-spp render.
    res["cycles_exact_64_vs_128"] = rel(os.path.join(bl, "paper_cycles_128_still.exr"), cyc64)
    log(f"eevee {res['eevee']}, cycles-lit {res['cycles_lit']}")
    for route in ("cycles-lit", "exact"):
        blender("sphere", paper, mat, os.path.join(bl, "paper"), "--samples", 64, "--route", route)
    a = pixels(os.path.join(bl, "paper_sphere_exact.exr"))
    b = pixels(os.path.join(bl, "paper_sphere_cycles-lit.exr"))
    png(np.concatenate([a, b], 1), os.path.join(args.docs, "blender_sphere_shadow.png"))

    # 3. Two frames of a shape key toward the flat cloth.
    verts, rest = read_obj(os.path.join(ROOT, "testscenes", "paper", "cloth.obj"))
    target = flat_target(verts)
    value = 0.5
    anim = os.path.join(bl, "anim")
    os.makedirs(anim, exist_ok=True)
    write_obj(os.path.join(anim, "flat.obj"), target, rest)
    write_obj(os.path.join(anim, "frame2.obj"), (1 - value) * verts + value * target, rest)
    with open(paper) as f:
        s = json.load(f)
    s["objects"][0]["mesh"] = os.path.join(anim, "frame2.obj")
    with open(os.path.join(anim, "frame2.json"), "w") as f:
        json.dump(s, f, indent=1)
    ref2 = os.path.join(anim, "ref_frame2.exr")
    res["anim_reference_seconds"] = reference(exe, os.path.join(anim, "frame2.json"), ref2)
    blender("anim", paper, mat, os.path.join(anim, "blender"), "--samples", 64, "--target",
            os.path.join(anim, "flat.obj"), "--value", value)
    res["anim"] = {"value": value,
                   "frame1": errors(ref_paper, os.path.join(anim, "blender_frame1.exr"))[0],
                   "frame2": errors(ref2, os.path.join(anim, "blender_frame2.exr"))[0]}
    rows = [np.concatenate([pixels(ref_paper), pixels(ref2)], 1),
            np.concatenate([pixels(os.path.join(anim, "blender_frame1.exr")),
                            pixels(os.path.join(anim, "blender_frame2.exr"))], 1)]
    png(np.concatenate(rows, 0), os.path.join(args.docs, "blender_anim.png"))
    log(f"anim {res['anim']}")

    # 4. The README strip: the key light circles the cloth.
    frames = 4
    strip = os.path.join(bl, "strip")
    os.makedirs(strip, exist_ok=True)
    blender("strip", paper, mat, os.path.join(strip, "blender"), "--samples", 64, "--frames",
            frames)
    up = np.array(s["camera"]["up"], float)
    up /= np.linalg.norm(up)
    refs, res["strip"] = [], []
    for f in range(frames):
        ang = 2 * math.pi * f / frames
        d = np.array(s["lights"][0]["direction"], float)
        # Rodrigues: the same turn blender_frames.py keys on the sun
        d = d * math.cos(ang) + np.cross(up, d) * math.sin(ang) + up * up.dot(d) * (1 - math.cos(ang))
        sf = json.loads(json.dumps(s))
        sf["objects"][0]["mesh"] = os.path.join(ROOT, "testscenes", "paper", "cloth.obj")
        sf["lights"][0]["direction"] = d.tolist()
        path = os.path.join(strip, f"turn{f}.json")
        with open(path, "w") as fh:
            json.dump(sf, fh, indent=1)
        ref = os.path.join(strip, f"ref_turn{f}.exr")
        reference(exe, path, ref, spp=16, quarter=False)
        refs.append(ref)
        res["strip"].append(errors(ref, os.path.join(strip, f"blender_turn{f}.exr"))[0])
    top = np.concatenate([pixels(os.path.join(strip, f"blender_turn{f}.exr"))
                          for f in range(frames)], 1)
    bottom = np.concatenate([pixels(r) for r in refs], 1)
    png(np.concatenate([top, bottom], 0), os.path.join(args.docs, "blender_strip.png"))
    log(f"strip {res['strip']}")

    # 5. Render times at equal noise (Cycles: material, per-scene bake).
    bake = os.path.join(out, "bake_adaptive_K16_3tpp")
    timing = {}
    for name, folder in (("material", mat), ("per_scene_bake", bake)):
        if not os.path.isdir(folder):
            continue
        row = {}
        for spp, seed in ((16, 1), (16, 2), (64, 1)):
            o = os.path.join(bl, f"time_{name}_{spp}_{seed}.exr")
            _, _, err = run(["blender", "-b", "--factory-startup", "--python-exit-code", "1",
                             "-P", os.path.join(ROOT, "blender_addon", "headless_render.py"),
                             "--", paper, folder, o, "--samples", str(spp), "--seed", str(seed),
                             "--timings", o + ".json"])
            with open(o + ".json") as fh:
                row[f"{spp}_{seed}"] = json.load(fh)["render_seconds"]
        sigma16 = rel(os.path.join(bl, f"time_{name}_16_1.exr"),
                      os.path.join(bl, f"time_{name}_16_2.exr")) / math.sqrt(2)
        per_spp = (row["64_1"] - row["16_1"]) / 48.0
        spp_2pct = 16 * (sigma16 / 0.02) ** 2
        timing[name] = {"seconds_16spp": row["16_1"], "seconds_64spp": row["64_1"],
                        "seconds_per_sample": per_spp, "noise_16spp": sigma16,
                        "spp_for_2pct_noise": spp_2pct,
                        "seconds_for_2pct_noise": row["16_1"] + per_spp * (spp_2pct - 16)}
    res["timing"] = timing
    log(f"timing {timing}")

    with open(os.path.join(bl, "results.json"), "w") as f:
        json.dump(res, f, indent=2)
    log(f"done: {bl}/results.json")


if __name__ == "__main__":
    main()
