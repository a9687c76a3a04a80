#!/usr/bin/env python3
"""Issue 15's figures for the cloth material, measured on this machine:
one material bake of the paper cloth (the defaults), rendered unchanged by
lookup-render in four scenes (the paper scene; its key light grazing and its
point light on the other side; a grazing camera; the camera 4 x farther),
each against that scene's converged reference (render, 64 spp, a quarter of
the march step, no light roulette, seed 7). Also: the per-scene adaptive bake
(K16, 3 texels per pixel) beside it, a direct render at 4 spp on the far
camera, error against size over --max-error, and the speed of both steps.

Errors are relative RMSE over RGB (clothbake compare), over the whole image
and over the cloth's interior (pixels whose reference alpha is >= 0.95 with
all 8 neighbours so): a 4-spp image's silhouette pixels carry coverage noise
that no shading removes.

    /usr/bin/python3 lab/material_accuracy/measure.py [--out DIR] [--exe EXE]

Writes DIR/results.json, DIR/results.md, DIR/error_vs_size.png and
comparison sheets; references are kept in DIR and reused.
"""
import argparse
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from material_measure import errors, folder_bytes, log, run  # noqa: E402

VARIANTS = ["paper", "grazing_light", "grazing_camera", "far_camera"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "material"))
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "baker", "clothbake"))
    ap.add_argument("--errors", default="0.2,0.1,0.05,0.02", help="--max-error values for the size curve")
    ap.add_argument("--plot-only", action="store_true", help="redraw the size curve from results.json")
    args = ap.parse_args()
    exe, out = args.exe, args.out
    if args.plot_only:
        with open(os.path.join(out, "results.json")) as f:
            plot(json.load(f)["size_curve"], out)
        return
    os.makedirs(out, exist_ok=True)
    scenes = os.path.join(out, "scenes")
    run([sys.executable, os.path.join(HERE, "variants.py"),
         os.path.join(ROOT, "testscenes", "paper", "scene.json"), scenes])
    res = {"machine": os.uname().nodename, "cpus": os.cpu_count()}

    # References (kept: about 7 minutes each on 2 cores).
    for v in VARIANTS:
        ref = os.path.join(out, f"ref_{v}.exr")
        with open(os.path.join(scenes, f"{v}.json")) as f:
            s = json.load(f)
        r = s.setdefault("render", {})
        r.update(step_cells=r.get("step_cells", 0.5) / 4, light_roulette=0.0, seed=7)
        key = json.dumps(s, sort_keys=True)
        key_path = ref + ".scene.json"
        if os.path.exists(ref) and os.path.exists(key_path) and open(key_path).read() == key:
            continue
        ref_scene = os.path.join(scenes, f"ref_{v}.json")
        with open(ref_scene, "w") as f:
            f.write(key)
        log(f"reference {v} (64 spp, quarter step)")
        secs, _, _ = run([exe, "render", ref_scene, "-o", ref, "--spp", "64", "--quiet"])
        res[f"reference_seconds_{v}"] = secs
        with open(key_path, "w") as f:
            f.write(key)

    # The default material, baked once.
    mat = os.path.join(out, "material_default")
    log("material bake (defaults)")
    secs, stdout, _ = run([exe, "material", os.path.join(scenes, "paper.json"), "-o", mat, "--quiet"])
    res["bake"] = dict(json.loads(stdout), wall_seconds=secs, bytes_on_disk=folder_bytes(mat))

    # Each scene from the one material, 4 and 64 spp.
    res["scenes"] = {}
    for v in VARIANTS:
        scene = os.path.join(scenes, f"{v}.json")
        ref = os.path.join(out, f"ref_{v}.exr")
        row = {}
        for spp in (4, 64):
            img = os.path.join(out, f"material_{v}_{spp}spp.exr")
            wall, _, err = run([exe, "lookup-render", scene, mat, "-o", img, "--spp", str(spp)])
            loop = float(re.search(r"pixel loop ([0-9.]+) s", err).group(1))
            whole, interior = errors(ref, img)
            row[f"{spp}spp"] = {"relative_rmse": whole, "interior_relative_rmse": interior,
                                "pixel_loop_seconds": loop, "wall_seconds": wall}
        a, b = os.path.join(out, f"material_{v}_4spp.exr"), os.path.join(out, f"material_{v}_64spp.exr")
        whole, interior = errors(b, a)
        row["4spp_vs_own_64spp"] = {"relative_rmse": whole, "interior_relative_rmse": interior}
        run([exe, "compare", ref, os.path.join(out, f"material_{v}_64spp.exr"),
             "--sheet", os.path.join(out, f"sheet_{v}.png")])
        res["scenes"][v] = row
        log(f"{v}: {json.dumps(row)}")

    # Beside it: a direct render at 4 spp of the far camera, and the paper
    # scene's per-scene adaptive bake (K16, 3 texels per pixel).
    img = os.path.join(out, "render_far_camera_4spp.exr")
    wall, _, _ = run([exe, "render", os.path.join(scenes, "far_camera.json"), "-o", img, "--spp", "4", "--quiet"])
    whole, interior = errors(os.path.join(out, "ref_far_camera.exr"), img)
    res["render_far_4spp"] = {"relative_rmse": whole, "interior_relative_rmse": interior, "wall_seconds": wall}
    bake = os.path.join(out, "bake_adaptive_K16_3tpp")
    secs, _, _ = run([exe, "bake", os.path.join(scenes, "paper.json"), "-o", bake, "--adaptive",
                      "--directions", "16", "--spp", "2", "--texels-per-pixel", "3", "--quiet"])
    img = os.path.join(out, "bake_paper_4spp.exr")
    run([exe, "lookup-render", os.path.join(scenes, "paper.json"), bake, "-o", img, "--spp", "4", "--quiet"])
    whole, interior = errors(os.path.join(out, "ref_paper.exr"), img)
    res["per_scene_bake_paper"] = {"relative_rmse": whole, "interior_relative_rmse": interior,
                                   "bake_seconds": secs, "bytes_on_disk": folder_bytes(bake)}

    # Error against size: the same bake at several --max-error.
    curve = []
    for e in [float(x) for x in args.errors.split(",")]:
        folder = mat if abs(e - 0.05) < 1e-9 else os.path.join(out, f"material_e{e}")
        if folder != mat:
            log(f"material bake --max-error {e}")
            secs, stdout, _ = run([exe, "material", os.path.join(scenes, "paper.json"), "-o", folder,
                                   "--quiet", "--max-error", str(e)])
        img = os.path.join(out, f"size_e{e}.exr")
        run([exe, "lookup-render", os.path.join(scenes, "paper.json"), folder, "-o", img, "--spp", "64", "--quiet"])
        whole, interior = errors(os.path.join(out, "ref_paper.exr"), img)
        with open(os.path.join(folder, "manifest.json")) as f:
            m = json.load(f)
        curve.append({"max_error": e, "bytes_on_disk": folder_bytes(folder), "max_rank": m["max_rank"],
                      "mean_rank": sum(m["ranks"]) / len(m["ranks"]),
                      "relative_rmse": whole, "interior_relative_rmse": interior})
        log(f"size curve: {curve[-1]}")
    res["size_curve"] = curve

    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(res, f, indent=2)
    plot(curve, out)
    log(f"done: {out}/results.json")


def plot(curve, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    mb = [c["bytes_on_disk"] / 2 ** 20 for c in curve]
    ax.plot(mb, [c["relative_rmse"] for c in curve], "o-", label="whole image")
    ax.plot(mb, [c["interior_relative_rmse"] for c in curve], "s--", label="cloth interior")
    for c, x in zip(curve, mb):
        ax.annotate(f"E={c['max_error']}, rank<={c['max_rank']}", (x, c["relative_rmse"]),
                    fontsize=7, xytext=(4, 4), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_xlabel("material on disk (MiB)")
    ax.set_ylabel("relative RMSE against the reference")
    ax.set_title("paper scene, 64 spp, from one material (R32 K16 KL10)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_size.png"), dpi=110)


if __name__ == "__main__":
    main()
