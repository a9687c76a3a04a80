#!/usr/bin/env python3
"""Light fields where cells are opaque (docs/design/material.md, "Opaque cells"):

    lab/opaque_cells/opaque_cells.py CLOTHBAKE WORK_DIR [--chart OUT.png] [--only N ...]

A plain weave of thick yarn (2.12 mm apart and as wide, 0.87 mm thick, as
the overshot tw_honeysuckle's threads; randomness out) on the paper scene's
folds, camera and lights at 40 repeats per UV. At the paper's sigma of 40 per
mm a field cell of its densest fibre holds an optical depth of 2.2 at 2 field
points per cell edge (the paper's own cloth: 0.45 to 0.55).

For each way of reading the light fields (`--light-fields`, and the
interpolated fields at 1, 2 and 4 points per cell edge): the whole-repeat
material's bake time (one run) and lookup-render at 64 spp against the
quarter-step reference at 64 spp, `clothbake compare`'s relative RMSE and
the image's mean over the reference's. Writes WORK_DIR/results.json; with
--chart, error against bake time; --only runs those rows of METHODS (from 0:
3 is the layer march) and keeps the other rows a results.json already holds.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from paper_runs import run, write_paper_scene  # noqa: E402
YARN = {"twist_deg": 0.0, "spacing_mm": 2.12, "width_mm": 2.12, "thickness_mm": 0.87,
        "color": [0.6, 0.45, 0.3]}
METHODS = [("interpolated, 1 point per cell edge", ["--light-fields", "interpolated",
                                                    "--field-supersample", "1"]),
           ("interpolated, 2 (the default before)", ["--light-fields", "interpolated"]),
           ("interpolated, 4", ["--light-fields", "interpolated", "--field-supersample", "4"]),
           ("layer march, 2 (auto here)", ["--light-fields", "layer-march"])]


def mean_ratio(ref, img):
    import numpy as np
    import OpenImageIO as oiio
    a = oiio.ImageBuf(ref).get_pixels(oiio.FLOAT)[..., :3]
    b = oiio.ImageBuf(img).get_pixels(oiio.FLOAT)[..., :3]
    cloth = a.sum(-1) > 1e-4
    return float(b[cloth].mean() / a[cloth].mean())


def measure(exe, work, only=None):
    cloth = {"name": "plain_thick", "weave": {"pattern": "plain"},
             "density": {"noise_amplitude": 0.0}, "shading": {"variation": 0.0},
             "warp": dict(YARN), "weft": dict(YARN)}
    cloth_path = os.path.join(work, "cloth.json")
    with open(cloth_path, "w") as f:
        json.dump(cloth, f, indent=1)
    for ref in (False, True):
        write_paper_scene(cloth_path, 40, os.path.join(work, "ref.json" if ref else "scene.json"),
                          ref)
    ref = os.path.join(work, "ref.exr")
    if not os.path.exists(ref):
        run([exe, "render", os.path.join(work, "ref.json"), "-o", ref, "--spp", "64", "--quiet"])
    old = os.path.join(work, "results.json")
    kept = {r["method"]: r for r in json.load(open(old))} if only and os.path.exists(old) else {}
    out = []
    for n, (label, flags) in enumerate(METHODS):
        if only is not None and n not in only:
            if label in kept:
                out.append(kept[label])
            continue
        mat = os.path.join(work, f"material_{n}")
        t, text = run([exe, "material", os.path.join(work, "scene.json"), "-o", mat, "--quiet"]
                      + flags)
        img = os.path.join(work, f"lookup_{n}.exr")
        run([exe, "lookup-render", os.path.join(work, "scene.json"), mat, "-o", img, "--spp", "64",
             "--quiet"])
        _, cmp = run([exe, "compare", ref, img, "--json"])
        r = {"method": label, "flags": flags, "bake_seconds": t,
             "relative_rmse": json.loads(cmp)["relative_rmse"], "mean_ratio": mean_ratio(ref, img),
             "light_fields": json.loads(text.strip().splitlines()[-1]).get("light_fields")}
        print(f"{label}: {r['relative_rmse'] * 100:.1f} %, mean x{r['mean_ratio']:.3f}, "
              f"bake {t:.0f} s", flush=True)
        out.append(r)
    with open(os.path.join(work, "results.json"), "w") as f:
        json.dump(out, f, indent=1)
    return out


def chart(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    for n, r in enumerate(results):
        march = r["flags"][1] == "layer-march"
        ax.plot(r["bake_seconds"], 100 * r["relative_rmse"], "s" if march else "o",
                color="C1" if march else "C0")
        ax.annotate(f"{r['method']}\nmean x{r['mean_ratio']:.3f}",
                    (r["bake_seconds"], 100 * r["relative_rmse"]), textcoords="offset points",
                    xytext=(6, 4 if n % 2 else -20), fontsize=7)
    ax.set_xlabel("whole-repeat material bake (s, 2 cores, one run)")
    ax.set_ylabel("lookup-render 64 spp: relative RMSE per pixel (%)")
    ax.set_title("Light fields on opaque cells: a 2.12 mm plain weave, paper scene", fontsize=10)
    ax.set_ylim(0, 100 * max(r["relative_rmse"] for r in results) * 1.25)
    ax.set_xlim(0, max(r["bake_seconds"] for r in results) * 1.6)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--chart-only":
        # lab/opaque_cells/opaque_cells.py --chart-only WORK_DIR OUT.png
        chart(json.load(open(os.path.join(sys.argv[2], "results.json"))), sys.argv[3])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exe")
    ap.add_argument("work")
    ap.add_argument("--chart", help="PNG: error against bake time")
    ap.add_argument("--only", type=int, nargs="+", help="rows of METHODS to run (from 0)")
    a = ap.parse_args()
    work = os.path.abspath(a.work)
    os.makedirs(work, exist_ok=True)
    results = measure(os.path.abspath(a.exe), work, a.only)
    if a.chart:
        chart(results, a.chart)
    return 0


if __name__ == "__main__":
    sys.exit(main())
