#!/usr/bin/python3
"""Compares clothbake's reference render of a scene with Cycles' render of the
same scene as a real volume (lab/cycles_check/cycles_check.sh; docs/design/results.md, "An
independent check: Cycles real volumes").

Usage:
  cycles_check_report.py NAME CLOTHBAKE CB.exr CYCLES_SEED_A.exr CYCLES_SEED_B.exr OUT_DIR
      [--figure FIGURE.png] [--min-psnr DB] [--min-psnr4 DB] [--ratio-range LO,HI]

The two Cycles renders have the same sample count and different seeds; their
mean is the Cycles picture (OUT_DIR/NAME_cycles.exr) and their difference
measures its noise: the noise of the mean per pixel and channel is
rms(A - B) / 2 (var(A - B) = 2 s^2 for per-render noise s; the mean has s^2 / 2).

Figures (all over R, G, B; clothbake is the reference):
- `clothbake compare --json` of the Cycles mean against clothbake: RMSE,
  relative RMSE (RMSE / clothbake's mean), PSNR with clothbake's maximum as
  the peak; again after 4 x 4 box averaging (--downsample 4), which leaves a
  16th of the per-pixel noise variance;
- the mean ratio Cycles / clothbake over the cloth: pixels where clothbake's
  alpha is above 0.5, eroded by 2 pixels (the whole frame in both check
  scenes), per channel and over R + G + B, with its noise standard deviation;
- the see-through ratio over the cloth: mean (1 - alpha) of Cycles over
  clothbake's (alpha = 1 - transmittance in both: a direct check of the
  extinction, independent of the lights);
- the noise figures: the Cycles mean's noise RMSE, relative and as a PSNR (the
  PSNR the comparison would have if the two renderers agreed exactly), and
  the systematic part of the relative RMSE, sqrt(total^2 - noise^2).

Writes OUT_DIR/NAME_check.json and, with --figure, a PNG: clothbake |
Cycles (both exposed so that clothbake's 99th percentile is 0.7, sRGB) |
difference (Cycles - clothbake over R + G + B, red brighter, blue
darker, saturating at +-25% of clothbake's mean). With --min-psnr (full
resolution), --min-psnr4 (after 4 x 4 box averaging) or --ratio-range it
exits 1 (naming each failed bound) when a bound fails.
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from report_images import erode, read_float, srgb  # noqa: E402


def write_exr(path, img):
    spec = oiio.ImageSpec(img.shape[1], img.shape[0], img.shape[2], oiio.FLOAT)
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(img.astype(np.float32))
    out.close()


def compare(clothbake, ref, test, downsample=1):
    cmd = [clothbake, "compare", ref, test, "--json"]
    if downsample > 1:
        cmd += ["--downsample", str(downsample)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    j = json.loads(out)
    return {k: j[k] for k in ("rmse", "relative_rmse", "psnr", "reference_peak", "reference_mean",
                              "max_error")}


def figure(path, name, cb, cy, exposure, diff_scale, title_cb, title_cy):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    h, w = cb.shape[:2]
    fig, axes = plt.subplots(1, 3, figsize=(3 * 3.2, 3.2 * h / w + 0.5), dpi=100,
                             constrained_layout=True)
    axes[0].imshow(srgb(cb[..., :3] * exposure), interpolation="nearest")
    axes[0].set_title(title_cb, fontsize=9)
    axes[1].imshow(srgb(cy[..., :3] * exposure), interpolation="nearest")
    axes[1].set_title(title_cy, fontsize=9)
    d = (cy[..., :3] - cb[..., :3]).sum(axis=2)
    im = axes[2].imshow(d, cmap="RdBu_r", vmin=-diff_scale, vmax=diff_scale, interpolation="nearest")
    axes[2].set_title("Cycles - clothbake (R+G+B)", fontsize=9)
    fig.colorbar(im, ax=axes[2], shrink=0.8)
    for a in axes:
        a.set_xticks([])
        a.set_yticks([])
    fig.suptitle(name, fontsize=10)
    fig.savefig(path)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for positional in ("name", "clothbake", "cb_path", "a_path", "b_path", "out_dir"):
        ap.add_argument(positional)
    ap.add_argument("--figure")
    ap.add_argument("--min-psnr")
    ap.add_argument("--min-psnr4")
    ap.add_argument("--ratio-range")
    args = ap.parse_args()
    opt = {"figure": args.figure, "min-psnr": args.min_psnr, "min-psnr4": args.min_psnr4,
           "ratio-range": args.ratio_range}
    name, clothbake, cb_path, a_path, b_path, out_dir = (
        args.name, args.clothbake, args.cb_path, args.a_path, args.b_path, args.out_dir)
    cb, a, b = read_float(cb_path), read_float(a_path), read_float(b_path)
    if cb.shape[:2] != a.shape[:2] or a.shape != b.shape:
        sys.exit("cycles_check_report.py: image sizes differ: %s %s %s" % (cb.shape, a.shape, b.shape))
    cy = 0.5 * (a + b)
    cy_path = os.path.join(out_dir, "%s_cycles.exr" % name)
    write_exr(cy_path, cy)

    # Mask: the cloth, away from its outline.
    mask = erode(cb[..., 3] > 0.5, 2)
    npix = int(mask.sum())
    if npix == 0:
        sys.exit("cycles_check_report.py: %s: no cloth pixels" % name)
    cb_rgb, cy_rgb = cb[..., :3][mask], cy[..., :3][mask]
    half_diff = 0.5 * (a[..., :3] - b[..., :3])  # noise of the mean, one draw per pixel
    ratio_rgb = (cy_rgb.mean(axis=0) / cb_rgb.mean(axis=0)).tolist()
    ratio = float(cy_rgb.sum() / cb_rgb.sum())
    # Standard deviation of the ratio from the Cycles noise (pixels independent).
    ratio_sigma = float(half_diff[mask].sum(axis=1).std() * math.sqrt(npix) / cb_rgb.sum())

    full = compare(clothbake, cb_path, cy_path)
    box4 = compare(clothbake, cb_path, cy_path, 4)
    noise_rmse = float(np.sqrt((half_diff ** 2).mean()))
    noise_rel = noise_rmse / full["reference_mean"]
    noise_psnr = 20 * math.log10(full["reference_peak"] / noise_rmse) if noise_rmse > 0 else math.inf
    sys_rel = math.sqrt(max(full["relative_rmse"] ** 2 - noise_rel ** 2, 0.0))
    # 4 x 4 box average: per-pixel noise variance / 16 (independent pixels).
    sys_rel4 = math.sqrt(max(box4["relative_rmse"] ** 2 - noise_rel ** 2 / 16, 0.0))
    see_cb, see_cy = float((1 - cb[..., 3][mask]).mean()), float((1 - cy[..., 3][mask]).mean())
    result = {
        "name": name,
        "clothbake": cb_path,
        "cycles": [a_path, b_path],
        "cycles_mean": cy_path,
        "cloth_pixels": npix,
        "mean_ratio": ratio,
        "mean_ratio_rgb": ratio_rgb,
        "mean_ratio_noise_sigma": ratio_sigma,
        "see_through_clothbake": see_cb,
        "see_through_cycles": see_cy,
        "see_through_ratio": see_cy / see_cb if see_cb > 0 else None,
        "clothbake_mean_rgb": cb_rgb.mean(axis=0).tolist(),
        "cycles_mean_rgb": cy_rgb.mean(axis=0).tolist(),
        "compare": full,
        "compare_4x4": box4,
        "noise_rmse": noise_rmse,
        "noise_relative_rmse": noise_rel,
        "noise_psnr": noise_psnr,
        "systematic_relative_rmse": sys_rel,
        "systematic_relative_rmse_4x4": sys_rel4,
    }
    failures = []
    if opt["min-psnr"] is not None and full["psnr"] < float(opt["min-psnr"]):
        failures.append("PSNR %.2f dB < %s dB" % (full["psnr"], opt["min-psnr"]))
    if opt["min-psnr4"] is not None and box4["psnr"] < float(opt["min-psnr4"]):
        failures.append("PSNR after 4 x 4 averaging %.2f dB < %s dB" % (box4["psnr"], opt["min-psnr4"]))
    if opt["ratio-range"] is not None:
        lo, hi = (float(x) for x in opt["ratio-range"].split(","))
        if not lo <= ratio <= hi:
            failures.append("mean ratio %.4f outside [%g, %g]" % (ratio, lo, hi))
    result["bounds"] = {"min_psnr": opt["min-psnr"], "min_psnr4": opt["min-psnr4"], "ratio_range": opt["ratio-range"],
                        "failures": failures}
    with open(os.path.join(out_dir, "%s_check.json" % name), "w") as f:
        json.dump(result, f, indent=2)
    print("cycles_check %s: mean ratio %.4f (+-%.4f noise; RGB %s), PSNR %.2f dB (noise alone %.2f), "
          "rel RMSE %.2f%% (noise %.2f%%, systematic %.2f%%), 4x4: PSNR %.2f dB, rel RMSE %.2f%%"
          % (name, ratio, ratio_sigma, " ".join("%.4f" % r for r in ratio_rgb), full["psnr"],
             noise_psnr, 100 * full["relative_rmse"], 100 * noise_rel, 100 * sys_rel,
             box4["psnr"], 100 * box4["relative_rmse"]), flush=True)
    print("cycles_check %s: see-through (1 - alpha) clothbake %.4f, Cycles %.4f" % (name, see_cb, see_cy))
    if opt["figure"]:
        diff_scale = 0.25 * 3 * full["reference_mean"]
        exposure = 0.7 / np.percentile(cb[..., :3], 99)  # the same for both pictures
        figure(opt["figure"], "%s: PSNR %.1f dB, mean ratio %.4f" % (name, full["psnr"], ratio), cb, cy,
               exposure, diff_scale, "clothbake render (isotropic)",
               "Cycles real volume, volume_bounces 0")
    for f in failures:
        print("FAIL %s: %s" % (name, f), flush=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
