"""Image helpers the report scripts share (cycles_check/cycles_check_report.py,
cycles_timing/cycles_timing_report.py, which put lab/common/ on sys.path):
reading an image as floats, the sRGB curve for figures, and eroding a cloth
mask so edge pixels stay out of a statistic."""

import os
import sys

import numpy as np
import OpenImageIO as oiio


def read_float(path):
    """The image at `path` as a float64 array (height, width, channels); exits
    naming the running script and the file if OpenImageIO cannot read it."""
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit("%s: cannot read %s: %s" % (os.path.basename(sys.argv[0]), path, buf.geterror()))
    return buf.get_pixels(oiio.FLOAT).astype(np.float64)


def srgb(x):
    """Linear values to sRGB-encoded ones in [0, 1], for PNG figures."""
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def erode(mask, k):
    """`mask` shrunk by k pixels: True only where the whole (2k+1)^2
    neighbourhood is. np.roll wraps: the frame's own border counts as cloth
    only if the cloth reaches it on both sides, as in the check scenes."""
    out = mask.copy()
    for dy in range(-k, k + 1):
        for dx in range(-k, k + 1):
            out &= np.roll(np.roll(mask, dy, 0), dx, 1)
    return out
