#!/usr/bin/python3
"""Difference maps of several Cycles set-ups against one clothbake picture,
side by side (the systematic-difference table of docs/design/results.md, "An
independent check: Cycles real volumes").

Usage: cycles_check_variants.py OUT.png CLOTHBAKE.exr LABEL=CYCLES.exr...

Each panel: Cycles - clothbake summed over R, G, B, red brighter, blue
darker, all panels on the same scale (+-25% of clothbake's mean), titled
with the label and the PSNR (clothbake's maximum as the peak).
"""
import math
import sys

import matplotlib
import numpy as np
import OpenImageIO as oiio

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit("cycles_check_variants.py: cannot read %s: %s" % (path, buf.geterror()))
    return buf.get_pixels(oiio.FLOAT).astype(np.float64)[..., :3]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out, cb = sys.argv[1], read(sys.argv[2])
    panels = [a.split("=", 1) for a in sys.argv[3:]]
    scale = 0.25 * 3 * cb.mean()
    h, w = cb.shape[:2]
    cols = min(3, len(panels))
    rows = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(cols * 3.2, rows * 3.2 * h / w + 0.6), dpi=100,
                             constrained_layout=True, squeeze=False)
    for ax in axes.flat:
        ax.set_axis_off()
    for ax, (label, path) in zip(axes.flat, panels):
        cy = read(path)
        psnr = 20 * math.log10(cb.max() / math.sqrt(((cy - cb) ** 2).mean()))
        im = ax.imshow((cy - cb).sum(axis=2), cmap="RdBu_r", vmin=-scale, vmax=scale,
                       interpolation="nearest")
        ax.set_title("%s: %.1f dB" % (label, psnr), fontsize=9)
    fig.colorbar(im, ax=axes, shrink=0.6)
    fig.savefig(out)


if __name__ == "__main__":
    main()
