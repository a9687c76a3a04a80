#!/usr/bin/env python3
"""Issue 24's colour figures, measured on this machine: one colour-free
material of the paper cloth (the defaults, `--parts specular-warp-weft`),
rendered by lookup-render in the paper scene in its own colours and in two
other colourways without baking again, each against that colourway's
converged reference (render, 64 spp, a quarter of the march step, no light
roulette, seed 7), beside an RGB material baked for each colourway (the
colours baked in) and the RGB material of the paper colours.

Colourways:
  paper       warp [0.60, 0.09, 0.08], weft [0.55, 0.42, 0.10] (the paper's)
  blue_weft   the weft [0.10, 0.20, 0.60]
  stripes     warp.colors a 3-end stripe (red, cream, green: the colours
              repeat every 3 ends, the plain weave every 2, so q = 3 and the
              cloth's repeat is 6 ends), weft.colors 2 picks (ochre, navy)

Errors are relative RMSE over RGB, whole image and interior (lab/common/material_measure.py).

    /usr/bin/python3 lab/colourways/colourways.py [--out DIR] [--exe EXE]

Writes DIR/results.json, DIR/results.md and DIR/sheet.png; references are
kept in DIR and reused.
"""
import argparse
import json
import os
import shutil
import sys

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from material_measure import errors, folder_bytes, log, pixels, run  # noqa: E402

PAPER = os.path.join(ROOT, "testscenes", "paper")
COLOURWAYS = {
    "paper": {},
    "blue_weft": {"weft": {"color": [0.10, 0.20, 0.60]}},
    "stripes": {"warp": {"colors": [[0.60, 0.09, 0.08], [0.80, 0.75, 0.60], [0.10, 0.30, 0.10]]},
                "weft": {"colors": [[0.55, 0.42, 0.10], [0.05, 0.07, 0.25]]}},
}


def scene_dir(out, name, reference):
    """The paper scene in colourway `name` (its reference settings when
    `reference`): the scene, its cloth spec and the mesh, in one folder."""
    d = os.path.join(out, "scenes", name + ("_ref" if reference else ""))
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(PAPER, "cloth.json")) as f:
        cloth = json.load(f)
    for family, keys in COLOURWAYS[name].items():
        cloth[family].update(keys)
    with open(os.path.join(d, "cloth.json"), "w") as f:
        json.dump(cloth, f, indent=1)
    with open(os.path.join(PAPER, "scene.json")) as f:
        scene = json.load(f)
    if reference:
        r = scene.setdefault("render", {})
        r.update(step_cells=r.get("step_cells", 0.5) / 4, light_roulette=0.0, seed=7)
    shutil.copy(os.path.join(PAPER, "cloth.obj"), d)
    path = os.path.join(d, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def png(exr):
    a = np.clip(pixels(exr)[..., :3], 0, None)
    return np.where(a <= 0.0031308, 12.92 * a, 1.055 * np.power(a, 1 / 2.4) - 0.055).clip(0, 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "colourways"))
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "baker", "clothbake"))
    args = ap.parse_args()
    exe, out = args.exe, args.out
    os.makedirs(out, exist_ok=True)
    res = {"machine": os.uname().nodename, "cpus": os.cpu_count(), "colourways": {}}

    scenes = {n: scene_dir(out, n, False) for n in COLOURWAYS}
    for n in COLOURWAYS:
        ref = os.path.join(out, f"ref_{n}.exr")
        if not os.path.exists(ref):
            log(f"reference {n} (64 spp, quarter step)")
            secs, _, _ = run([exe, "render", scene_dir(out, n, True), "-o", ref, "--spp", "64", "--quiet"])
            log(f"  {secs:.0f} s")

    # The colour-free material once; an RGB material per colourway.
    mats = {}
    for label, scene, parts in [("free", scenes["paper"], "specular-warp-weft")] + \
            [(f"rgb_{n}", scenes[n], "rgb") for n in COLOURWAYS]:
        folder = os.path.join(out, f"material_{label}")
        log(f"material {label}")
        secs, stdout, _ = run([exe, "material", scene, "-o", folder, "--parts", parts, "--quiet"])
        report = json.loads(stdout.strip().splitlines()[-1])
        mats[label] = {"seconds": secs, "bytes": folder_bytes(folder),
                       "max_rank": json.load(open(os.path.join(folder, "manifest.json")))["max_rank"]}
        res.setdefault("materials", {})[label] = mats[label]
        res["materials"][label]["report_seconds"] = report.get("seconds")

    rows = []
    for n in COLOURWAYS:
        entry = {}
        imgs = []
        for label in ("free", f"rgb_{n}"):
            img = os.path.join(out, f"{n}_{label}.exr")
            secs, _, _ = run([exe, "lookup-render", scenes[n], os.path.join(out, f"material_{label}"),
                              "-o", img, "--spp", "64", "--quiet"])
            whole, interior = errors(os.path.join(out, f"ref_{n}.exr"), img)
            entry["free" if label == "free" else "rgb"] = {"whole": whole, "interior": interior,
                                                           "seconds": secs}
            imgs.append(img)
        # The two materials against each other: what colour-free parts cost.
        whole, interior = errors(imgs[1], imgs[0])
        entry["free_vs_rgb"] = {"whole": whole, "interior": interior}
        res["colourways"][n] = entry
        log(f"{n}: colour-free {entry['free']['whole']:.4f} / {entry['free']['interior']:.4f}, "
            f"rgb {entry['rgb']['whole']:.4f} / {entry['rgb']['interior']:.4f}, "
            f"free vs rgb {whole:.4f}")
        rows.append(np.concatenate([png(os.path.join(out, f"ref_{n}.exr")), png(imgs[0]), png(imgs[1])], 1))
    sheet = np.concatenate(rows, 0).astype(np.float32)
    buf = oiio.ImageBuf(oiio.ImageSpec(sheet.shape[1], sheet.shape[0], 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), sheet)
    buf.write(os.path.join(out, "sheet.png"))

    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    lines = ["| colourway | colour-free material: whole / interior | RGB material of that colourway | colour-free against RGB |",
             "|---|---|---|---|"]
    for n, e in res["colourways"].items():
        lines.append(f"| {n} | {e['free']['whole']:.3f} / {e['free']['interior']:.3f} | "
                     f"{e['rgb']['whole']:.3f} / {e['rgb']['interior']:.3f} | "
                     f"{e['free_vs_rgb']['whole']:.3f} / {e['free_vs_rgb']['interior']:.3f} |")
    lines.append("")
    lines.append("| material | bake wall (s) | folder (MB) | max rank |")
    lines.append("|---|---|---|---|")
    for label, m in res["materials"].items():
        lines.append(f"| {label} | {m['seconds']:.1f} | {m['bytes'] / 1e6:.1f} | {m['max_rank']} |")
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
