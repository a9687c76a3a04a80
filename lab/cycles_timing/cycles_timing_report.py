#!/usr/bin/python3
"""Turns the renders of lab/cycles_timing/cycles_volume_timing.sh into figures: noise
against samples and seconds for the two Cycles routes (the flat cloth as a
real volume; the same cloth drawn from a clothbake bake), the sample count
and seconds each needs for a noise level, and how far the two pictures are
apart.

Usage: cycles_timing_report.py OUT_DIR VOL_SAMPLES VOL_REF BAKE_SAMPLES BAKE_REF FIGURE.png
                               [MAT_SAMPLES MAT_REF]
  (sample lists comma-separated; file names as the driver writes them)

Noise is the relative RMSE of `clothbake compare`: the RMSE over every pixel's
R, G and B, divided by the mean R, G, B of the reference; the reference is the
same route rendered with more samples (Nref) and another seed. Its own noise
adds in quadrature; it is the same route's, so where the noise goes as
1/sqrt(N) the test's alone is m / sqrt(1 + N / Nref) (the "corrected"
figure; the raw one is kept). The sample count for a level T comes from
log-log interpolation between the measured points that bracket it, or,
beyond them, from the power law n = A N^-p fitted to the route's points with
N >= 16 (all points if fewer than 3 such; marked extrapolated); seconds at
that count from straight-line fits of render wall seconds and CPU seconds
against samples.

Writes OUT_DIR/cycles_timing.json, OUT_DIR/cycles_timing.csv and FIGURE.png
(volume render | baked render, sRGB).
"""
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from report_images import erode, read_float, srgb  # noqa: E402

LEVELS = [0.05, 0.03, 0.02, 0.01]


def rel_rmse(test, ref, mask=None):
    d2 = (test[..., :3] - ref[..., :3]) ** 2
    if mask is not None:
        return math.sqrt(d2[mask].mean()) / ref[..., :3][mask].mean()
    return math.sqrt(d2.mean()) / ref[..., :3].mean()


def box(img, f):
    h, w = img.shape[0] // f * f, img.shape[1] // f * f
    return img[:h, :w].reshape(h // f, f, w // f, f, -1).mean(axis=(1, 3))


def power_fit(samples, noise):
    x, y = np.log(np.array(samples, float)), np.log(np.array(noise, float))
    slope, icpt = np.polyfit(x, y, 1)
    return float(math.exp(icpt)), float(-slope)  # n = A N^-p


def samples_for(level, samples, noise, a, p):
    """Sample count reaching `level`: bracketing interpolation (log-log) or
    the power law; returns (N, extrapolated)."""
    pts = sorted(zip(samples, noise))
    for (n0, e0), (n1, e1) in zip(pts, pts[1:]):
        if e0 >= level >= e1 and e0 > e1:
            t = (math.log(e0) - math.log(level)) / (math.log(e0) - math.log(e1))
            return math.exp(math.log(n0) + t * (math.log(n1) - math.log(n0))), False
    if pts[0][1] <= level:
        return float(pts[0][0]), False  # already at the fewest samples measured
    return (a / level) ** (1.0 / p), True


def route(name, runs, ref_img, nref):
    samples = [r["samples"] for r in runs]
    raw = [rel_rmse(read_float(r["exr"]), ref_img) for r in runs]
    corrected = [m / math.sqrt(1.0 + n / nref) for m, n in zip(raw, samples)]
    tail = [i for i, n in enumerate(samples) if n >= 16]
    if len(tail) < 3:
        tail = list(range(len(samples)))
    a, p = power_fit([samples[i] for i in tail], [corrected[i] for i in tail])
    ns = np.array(samples, float)
    t0, t1 = np.polyfit(ns, np.array([r["render_seconds"] for r in runs]), 1)[::-1]  # t = t0 + t1 N
    c0, c1 = np.polyfit(ns, np.array([r["cpu_seconds"] for r in runs]), 1)[::-1]
    for run, m, n in zip(runs, raw, corrected):
        run["relative_rmse_raw"] = m
        run["relative_rmse"] = n
    levels = []
    for lv in LEVELS:
        n, extrap = samples_for(lv, samples, corrected, a, p)
        levels.append({"level": lv, "samples": n, "extrapolated": extrap,
                       "render_seconds": float(t0 + t1 * n), "cpu_seconds": float(c0 + c1 * n)})
    slopes = [-math.log(corrected[i + 1] / corrected[i]) / math.log(samples[i + 1] / samples[i])
              for i in range(len(samples) - 1)]
    return {"route": name, "runs": runs, "reference_samples": nref,
            "reference_noise_estimate": corrected[-1] * math.sqrt(samples[-1] / nref),
            "power_law": {"A": a, "p": p, "fitted_on_samples": [samples[i] for i in tail]},
            "local_exponents": slopes,
            "seconds_per_sample": float(t1), "seconds_fixed": float(t0),
            "cpu_seconds_per_sample": float(c1), "cpu_seconds_fixed": float(c0), "levels": levels}


def headless_runs(out, folder, prefix, samples, nref, steps):
    """The add-on's headless renders, one Blender process per sample count;
    the last entry is the reference (seed 7)."""
    runs = []
    for n in samples + [nref]:
        seed = 7 if n == nref and n not in samples else 1
        tag = "%s_s%d_seed%d" % (prefix, n, seed)
        with open(os.path.join(out, folder, tag + "_timings.json")) as f:
            ht = json.load(f)
        with open(os.path.join(out, folder, tag + "_clock.json")) as f:
            ck = json.load(f)
        runs.append({"samples": n, "seed": seed, "render_seconds": ht["render_seconds"],
                     "cpu_seconds": ck["renders"][0]["cpu_seconds"],
                     "process_seconds": steps[tag]["seconds"],
                     "exr": os.path.join(out, folder, tag + ".exr")})
    return runs


def main():
    if len(sys.argv) not in (7, 9):
        sys.exit(__doc__)
    out, vs, vref, bs, bref, figure = sys.argv[1:7]
    material_args = sys.argv[7:9]
    vs = [int(s) for s in vs.split(",")]
    bs = [int(s) for s in bs.split(",")]
    vref, bref = int(vref), int(bref)
    steps = {}
    with open(os.path.join(out, "steps.tsv")) as f:
        for line in f:
            w = line.rstrip("\n").split("\t")
            steps[w[0]] = {"seconds": float(w[2]) - float(w[1]), "load_before": float(w[3]),
                           "load_after": float(w[4]),
                           "cpu_seconds": float(w[5]) if len(w) > 5 else None}

    # Volume route: one Blender process renders the test counts, one the reference.
    with open(os.path.join(out, "vol", "volume_seed1_timing.json")) as f:
        vt = json.load(f)
    with open(os.path.join(out, "vol", "volume_seed7_timing.json")) as f:
        vrt = json.load(f)
    vol_ref = read_float(vrt["runs"][0]["exr"])
    vol = route("volume", vt["runs"], vol_ref, vref)
    vol["load_seconds"] = vt["load_seconds"]
    vol["process_seconds"] = steps["volume_renders"]["seconds"]
    vol["blender_startup_and_exit_seconds"] = (steps["volume_renders"]["seconds"] - vt["load_seconds"]
                                               - sum(r["render_seconds"] for r in vt["runs"]))
    vol["reference"] = {"samples": vref, "seed": 7, "render_seconds": vrt["runs"][0]["render_seconds"],
                        "cpu_seconds": vrt["runs"][0]["cpu_seconds"]}
    grid_path = os.path.join(out, "vol", "volume_grid_seed1_timing.json")
    if os.path.exists(grid_path):
        with open(grid_path) as f:
            g = json.load(f)["runs"][0]
        same = [r for r in vt["runs"] if r["samples"] == g["samples"]]
        vol["grid_colour"] = {"samples": g["samples"], "render_seconds": g["render_seconds"],
                              "albedo_render_seconds": same[0]["render_seconds"] if same else None}

    # Bake route: one Blender process per sample count (the add-on's headless route).
    bruns = []
    for n in bs + [bref]:
        seed = 7 if n == bref and n not in bs else 1
        tag = "bake_s%d_seed%d" % (n, seed)
        with open(os.path.join(out, "bakeroute", tag + "_timings.json")) as f:
            ht = json.load(f)
        with open(os.path.join(out, "bakeroute", tag + "_clock.json")) as f:
            ck = json.load(f)
        proc = steps[tag]["seconds"]
        bruns.append({"samples": n, "seed": seed, "render_seconds": ht["render_seconds"],
                      "cpu_seconds": ck["renders"][0]["cpu_seconds"],
                      "clock_wall_seconds": ck["renders"][0]["wall_seconds"],
                      "import_seconds": ht["import_seconds"], "apply_seconds": ht["apply_seconds"],
                      "process_seconds": proc,
                      "load_seconds": proc - ht["render_seconds"] - ht.get("write_seconds", 0.0),
                      "exr": os.path.join(out, "bakeroute", tag + ".exr")})
    bake_ref_run = bruns.pop()
    material = None
    if material_args:
        ms, mref = [int(x) for x in material_args[0].split(",")], int(material_args[1])
        mruns = headless_runs(out, "matroute", "material", ms, mref, steps)
        mat_ref_run = mruns.pop()
        material = route("material", mruns, read_float(mat_ref_run["exr"]), mref)
        material["reference"] = {k: mat_ref_run[k] for k in ("samples", "seed", "render_seconds",
                                                             "cpu_seconds")}
        material["clothbake_material"] = steps.get("clothbake_material")
    bake_ref = read_float(bake_ref_run["exr"])
    bake = route("bake", bruns, bake_ref, bref)
    bake["reference"] = {k: bake_ref_run[k] for k in ("samples", "seed", "render_seconds", "cpu_seconds")}
    bake["load_seconds_median"] = float(np.median([r["load_seconds"] for r in bruns]))
    with open(os.path.join(out, "bake", "manifest.json")) as f:
        manifest = json.load(f)
    bake["clothbake_bake"] = {"bake_seconds": manifest["statistics"]["bake_seconds"],
                              "command": steps.get("clothbake_bake"),
                              "direction_tiles": manifest["statistics"].get("direction_tiles"),
                              "texels": manifest["statistics"].get("texels"),
                              "bytes_on_disk": sum(os.path.getsize(os.path.join(out, "bake", f))
                                                   for f in os.listdir(os.path.join(out, "bake")))}

    # How different the pictures are: the two references, and each against
    # clothbake's own renderer; whole image, cloth interior (clothbake alpha 1,
    # 4 px from any edge), and 4 x 4 box-averaged (less of the noise).
    cb = read_float(os.path.join(out, "clothbake_render.exr"))
    lr_path = os.path.join(out, "lookup_render.exr")
    lr = read_float(lr_path) if os.path.exists(lr_path) else None
    interior = erode(cb[..., 3] > 0.5, 4)
    interior4 = box(interior[..., None].astype(float), 4)[..., 0] > 0.999
    pictures = {}
    for name, a, b in (("volume_vs_bake", vol_ref, bake_ref), ("volume_vs_clothbake_render", vol_ref, cb),
                       ("bake_vs_clothbake_render", bake_ref, cb),
                       ("bake_vs_lookup_render", bake_ref, lr),
                       ("lookup_render_vs_clothbake_render", lr, cb)):
        if a is None or b is None:
            continue
        ratio = (a[..., :3][interior].mean(axis=0) / b[..., :3][interior].mean(axis=0)).tolist()
        pictures[name] = {"relative_rmse": rel_rmse(a, b),
                          "relative_rmse_interior": rel_rmse(a, b, interior),
                          "relative_rmse_4x4": rel_rmse(box(a, 4), box(b, 4)),
                          "relative_rmse_interior_4x4": rel_rmse(box(a, 4), box(b, 4), interior4),
                          "mean_ratio_interior_rgb": ratio}
    pictures["interior_pixels"] = int(interior.sum())
    pictures["clothbake_render_spp"] = 16

    res = {"scene": "testscenes/flat/scene.json", "steps": steps,
           "light_units": json.load(open(os.path.join(out, "light_units.json"))),
           "tiled_volume": json.load(open(os.path.join(out, "tiled.json"))),
           "volume": vol, "bake": bake, "pictures": pictures}
    if material is not None:
        res["material"] = material
    with open(os.path.join(out, "cycles_timing.json"), "w") as f:
        json.dump(res, f, indent=2)
    with open(os.path.join(out, "cycles_timing.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["route", "samples", "seed", "render_seconds", "cpu_seconds",
                    "relative_rmse_raw", "relative_rmse"])
        for rt in [r for r in (vol, bake, material) if r is not None]:
            for r in rt["runs"]:
                w.writerow([rt["route"], r["samples"], r["seed"], "%.3f" % r["render_seconds"],
                            "%.3f" % r["cpu_seconds"], "%.5f" % r["relative_rmse_raw"],
                            "%.5f" % r["relative_rmse"]])
            ref = rt["reference"]
            w.writerow([rt["route"] + "_reference", ref["samples"], ref["seed"],
                        "%.3f" % ref["render_seconds"], "%.3f" % ref["cpu_seconds"], "", ""])
        w.writerow([])
        w.writerow(["route", "level", "samples", "render_seconds", "extrapolated"])
        for rt in [r for r in (vol, bake, material) if r is not None]:
            for lv in rt["levels"]:
                w.writerow([rt["route"], lv["level"], "%.1f" % lv["samples"],
                            "%.2f" % lv["render_seconds"], int(lv["extrapolated"])])

    # Figure: volume (reference) | bake (highest test count) | volume at about the bake's seconds.
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bshow = bake["runs"][-1]
    near = min(vol["runs"], key=lambda r: abs(math.log(r["render_seconds"] / bshow["render_seconds"])))
    panels = [(vol_ref, "real volume, %d spp: %.0f s" % (vref, vol["reference"]["render_seconds"])),
              (read_float(bshow["exr"]), "from the bake, %d spp: %.1f s" % (bshow["samples"], bshow["render_seconds"])),
              (read_float(near["exr"]), "real volume, %d spp: %.1f s" % (near["samples"], near["render_seconds"]))]
    h, w = vol_ref.shape[:2]
    fig, axes = plt.subplots(1, 3, figsize=(3 * w / 100, (h + 22) / 100), dpi=100)
    for ax, (img, title) in zip(axes, panels):
        ax.imshow(srgb(img[..., :3]), interpolation="nearest")
        ax.set_title(title, fontsize=8, pad=2)
        ax.axis("off")
    fig.subplots_adjust(left=0, right=1, bottom=0, top=(h / (h + 22)), wspace=0.01)
    tmp = figure + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    from PIL import Image
    im = Image.open(tmp).convert("RGB")
    if os.path.getsize(tmp) > 280_000:  # keep docs/images small: 256-colour palette
        im = im.quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    im.save(figure, optimize=True)
    os.remove(tmp)

    def show(rt):
        for r in rt["runs"]:
            print("%-6s %5d spp  %7.2f s wall %7.2f s CPU  noise %.4f (raw %.4f)"
                  % (rt["route"], r["samples"], r["render_seconds"], r["cpu_seconds"],
                     r["relative_rmse"], r["relative_rmse_raw"]))
        print("%-6s reference noise %.4f, power law p = %.3f (local %s), %.4f s per sample + %.2f s"
              % (rt["route"], rt["reference_noise_estimate"], rt["power_law"]["p"],
                 " ".join("%.2f" % e for e in rt["local_exponents"]), rt["seconds_per_sample"],
                 rt["seconds_fixed"]))
        for lv in rt["levels"]:
            print("%-6s level %.0f%%: %.1f spp, %.2f s wall, %.2f s CPU%s"
                  % (rt["route"], 100 * lv["level"], lv["samples"], lv["render_seconds"],
                     lv["cpu_seconds"], " (extrapolated)" if lv["extrapolated"] else ""))
    show(vol)
    show(bake)
    print(json.dumps(pictures, indent=1))
    print("figure %s: %d bytes" % (figure, os.path.getsize(figure)))


if __name__ == "__main__":
    main()
