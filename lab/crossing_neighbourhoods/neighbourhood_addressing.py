#!/usr/bin/env python3
"""What addressing a material by crossing neighbourhood would cost in a
rendered image (issue 24, "Locality"), measured before the layout is built.

    lab/crossing_neighbourhoods/neighbourhood_addressing.py CLOTHBAKE WORK_DIR [--draft diamond]

A neighbourhood-addressed material stores one block of texels per distinct
neighbourhood of crossings and reads each crossing through its
neighbourhood's block. This script makes such a material's pixels out of an
ordinary one, without a new layout: it bakes the whole repeat of a draft
whose threads fall on whole texels (the 8 x 8 point-twill diamond: 64
crossings, 17 distinct plus-1 neighbourhoods; 64 texels, 8 per thread), then
rewrites level 0 so that every crossing's block (its thread's span along x
times its pick's along y, in every view node's tile, every channel and
alpha) is replaced by
  mean      the mean of the blocks of all crossings with the same plus-1
            stencil (what a bake that averages a neighbourhood's crossings
            would store), or
  first     the block of the first such crossing (what a bake of one
            representative would store),
and the levels above by exact 2 x 2 box averages. The paper scene (its
camera, lights and folds) at 80 ends per UV is rendered by lookup-render
from the whole-repeat material and from both rewritten ones, against a
converged reference (64 spp, a quarter of the march step, no roulette).

`--no-randomness` takes the per-crossing randomness out of the cloth (as
neighbourhood_reach.py does), so that crossings with the same surroundings
differ only by the bake's noise. Prints relative RMSE (whole image, and
after a 4 x 4 box filter) and writes
WORK_DIR/results.json and WORK_DIR/sheet.png, with the sizes: the
whole-repeat folder's bytes, and the addressed layout's estimated as the
level images' bytes times neighbourhoods / crossings (one block per
neighbourhood instead of one per crossing) plus the light factors.

    lab/crossing_neighbourhoods/neighbourhood_addressing.py --chart OUT.png WORK_DIR...

draws size against error for the runs in WORK_DIRs (their results.json).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PAPER = os.path.join(ROOT, "testscenes", "paper")
ENDS = 8
TEXELS = 64


def diamond():
    """A 2/2 twill pointed both ways over 8 ends and 8 picks."""
    twill = lambda r, e: 1 if (e - r) % 4 in (0, 1) else 0  # noqa: E731
    point = lambda i: i if i < 4 else 7 - i                 # noqa: E731
    return [[twill(point(r), point(e)) for e in range(ENDS)] for r in range(ENDS)]


def plus1_keys(draft):
    """Per crossing (pick, end): its plus-shaped stencil of radius 1."""
    n_p, n_e = len(draft), len(draft[0])
    up = lambda p, e: draft[p % n_p][e % n_e]  # noqa: E731
    return {(p, e): (up(p - 1, e), up(p, e), up(p + 1, e), up(p, e - 1), up(p, e + 1))
            for p in range(n_p) for e in range(n_e)}


def run(cmd, log=None):
    print("  " + " ".join(os.path.basename(c) if i == 0 else c for i, c in enumerate(cmd)),
          flush=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL if log is None else log)


def read(path):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    return buf.get_pixels(oiio.FLOAT), spec


def write(path, values, spec):
    out = oiio.ImageSpec(spec)
    buf = oiio.ImageBuf(out)
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(values, dtype=np.float32))
    if not buf.write(path):
        raise RuntimeError(buf.geterror())


def rewrite(src, dst, draft, how):
    """Copies material `src` to `dst` with its level 0 addressed per plus-1
    neighbourhood (`how`: mean or first) and its levels above rebuilt."""
    if os.path.isdir(dst):
        shutil.rmtree(dst)
    shutil.copytree(src, dst)
    man = json.load(open(os.path.join(src, "manifest.json")))
    k, levels, r = man["directions"], man["levels"], man["texels"]
    centres = man["cloth"]["threads"]["warp"]["centres_mm"]
    n_p, n_e = len(draft), len(draft[0])
    assert r % n_e == 0 and r % n_p == 0 and len(centres) == n_e, "threads must fall on whole texels"
    tx, ty = r // n_e, r // n_p
    keys = plus1_keys(draft)
    groups = {}
    for c, key in keys.items():
        groups.setdefault(key, []).append(c)
    level0, spec = read(os.path.join(src, "level_0.exr"))      # (2K S, K S, channels)
    h, w, nc = level0.shape
    tiles = level0.reshape(2 * k, r, k, r, nc)                   # [row, y, col, x, c]
    # Thread e owns x in [e, e + 1) * spacing (centres at (e + 0.5) * spacing).
    out = tiles.copy()
    for members in groups.values():
        blocks = [tiles[:, p * ty:(p + 1) * ty, :, e * tx:(e + 1) * tx] for p, e in members]
        value = np.mean(blocks, axis=0) if how == "mean" else blocks[0]
        for p, e in members:
            out[:, p * ty:(p + 1) * ty, :, e * tx:(e + 1) * tx] = value
    current = out
    write(os.path.join(dst, "level_0.exr"), current.reshape(h, w, nc), spec)
    for m in range(1, levels):
        s = current.shape[1] // 2
        current = current.reshape(2 * k, s, 2, k, s, 2, nc).mean(axis=(2, 5))
        _, spec_m = read(os.path.join(src, f"level_{m}.exr"))
        write(os.path.join(dst, f"level_{m}.exr"), current.reshape(2 * k * s, k * s, nc), spec_m)
    return len(groups)


def pixels(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)


def rel_rmse(ref, img, box=1):
    a, b = pixels(ref), pixels(img)
    if box > 1:
        hh, ww = (a.shape[0] // box) * box, (a.shape[1] // box) * box
        a = a[:hh, :ww].reshape(hh // box, box, ww // box, box, 3).mean(axis=(1, 3))
        b = b[:hh, :ww].reshape(hh // box, box, ww // box, box, 3).mean(axis=(1, 3))
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(a ** 2)))


def sizes(whole, neighbourhoods, crossings):
    """The whole-repeat folder's bytes, and the addressed layout's estimate."""
    files = {f: os.path.getsize(os.path.join(whole, f)) for f in os.listdir(whole)}
    levels = sum(b for f, b in files.items() if f.startswith("level_"))
    return {"whole": sum(files.values()),
            "addressed": int(levels * neighbourhoods / crossings) + files["light_factors.exr"]}


def chart(out, work_dirs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for work, marker in zip(work_dirs, "os^D"):
        r = json.load(open(os.path.join(work, "results.json")))
        label = "no per-crossing randomness" if r.get("no_randomness") else "as generated"
        pts = [("whole repeat", r["bytes"]["whole"], r["whole"]["whole"]),
               ("plus-1, mean", r["bytes"]["addressed"], r["mean"]["whole"]),
               ("plus-1, first", r["bytes"]["addressed"], r["first"]["whole"])]
        ax.plot([p[1] / 1e6 for p in pts], [100 * p[2] for p in pts], marker, ls="none",
                label=label)
        for (name, b, e), dy in zip(pts, (4, -12, 6)):
            ax.annotate(name, (b / 1e6, 100 * e), textcoords="offset points", xytext=(6, dy),
                        fontsize=8)
    ax.set_xlabel("material folder (MB; addressed: estimated)")
    ax.set_ylabel("relative RMSE per pixel against the reference (%)")
    ax.set_title("8 x 8 diamond on the paper scene, lookup-render 64 spp")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def srgb(a):
    a = np.clip(a, 0, None)
    return np.where(a <= 0.0031308, 12.92 * a, 1.055 * np.power(a, 1 / 2.4) - 0.055).clip(0, 1)


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--chart":
        chart(sys.argv[2], sys.argv[3:])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exe")
    ap.add_argument("work")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--no-randomness", action="store_true",
                    help="take the per-crossing randomness out (density noise 0, shading "
                         "variation 0, no ply twist) and bake 16 cells per thread: what is "
                         "left between addressed and whole is the neighbourhood's reach")
    args = ap.parse_args()
    exe, work = os.path.abspath(args.exe), os.path.abspath(args.work)
    os.makedirs(work, exist_ok=True)
    draft = diamond()

    cloth = json.load(open(os.path.join(PAPER, "cloth.json")))
    cloth.pop("weave", None)
    cloth.update(name="diamond", weave={"draft": draft})
    cloth["resolution"].update(cells_x=32 * ENDS, cells_y=32 * ENDS)  # the paper's 32 per thread
    if args.no_randomness:
        cloth["density"]["noise_amplitude"] = 0.0
        cloth["shading"]["variation"] = 0.0
        for family in ("warp", "weft"):
            cloth[family]["twist_deg"] = 0.0
        cloth["resolution"].update(cells_x=16 * ENDS, cells_y=16 * ENDS)
    with open(os.path.join(work, "cloth.json"), "w") as f:
        json.dump(cloth, f, indent=1)
    scene = json.load(open(os.path.join(PAPER, "scene.json")))
    obj = scene["objects"][0]
    obj.update(mesh=os.path.join(PAPER, "cloth.obj"), cloth=os.path.join(work, "cloth.json"),
               repeats_per_uv=80 / ENDS)
    with open(os.path.join(work, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
    r = scene.setdefault("render", {})
    r.update(step_cells=r.get("step_cells", 0.5) / 4, light_roulette=0.0, seed=7)
    with open(os.path.join(work, "scene_ref.json"), "w") as f:
        json.dump(scene, f, indent=1)

    ref = os.path.join(work, "ref.exr")
    if not os.path.exists(ref):
        run([exe, "render", os.path.join(work, "scene_ref.json"), "-o", ref, "--spp", "64",
             "--quiet"])
    whole = os.path.join(work, "material_whole")
    if not os.path.exists(os.path.join(whole, "manifest.json")):
        run([exe, "material", os.path.join(work, "scene.json"), "-o", whole, "--texels",
             str(TEXELS), "--quiet"])
    results = {"draft": draft, "crossings": ENDS * ENDS, "no_randomness": args.no_randomness}
    images = [ref]
    for how in ("whole", "mean", "first"):
        folder = whole
        if how != "whole":
            folder = os.path.join(work, f"material_{how}")
            results["neighbourhoods"] = rewrite(whole, folder, draft, how)
        img = os.path.join(work, f"lookup_{how}.exr")
        run([exe, "lookup-render", os.path.join(work, "scene.json"), folder, "-o", img,
             "--spp", str(args.spp), "--quiet"])
        results[how] = {"whole": rel_rmse(ref, img), "box4": rel_rmse(ref, img, 4)}
        if how != "whole":
            results[how]["against_whole_material"] = rel_rmse(
                os.path.join(work, "lookup_whole.exr"), img)
        images.append(img)
        print(f"{how}: {results[how]}", flush=True)
    results["bytes"] = sizes(whole, results["neighbourhoods"], ENDS * ENDS)
    sheet = np.concatenate([srgb(pixels(p)) for p in images], axis=1).astype(np.float32)
    buf = oiio.ImageBuf(oiio.ImageSpec(sheet.shape[1], sheet.shape[0], 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), sheet)
    buf.write(os.path.join(work, "sheet.png"))
    with open(os.path.join(work, "results.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
