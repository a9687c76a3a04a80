"""What the cloth material's measurements share (material_accuracy/measure.py,
blender_measure.py, colourways/colourways.py): running a command timed,
reading an image's pixels, and the relative RMSE of an image against its
reference over the whole image and over the cloth's interior."""
import os
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio


def log(msg):
    print(f"[measure] {msg}", file=sys.stderr, flush=True)


def run(cmd):
    start = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr[-2000:])
    return time.perf_counter() - start, p.stdout, p.stderr


def pixels(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)


def errors(ref_path, img_path):
    """(whole image, interior) relative RMSE, as clothbake compare defines it:
    RMSE over RGB divided by the reference's mean RGB."""
    a, b = pixels(ref_path), pixels(img_path)
    mean = a[..., :3].mean()
    whole = np.sqrt(((a[..., :3] - b[..., :3]) ** 2).mean()) / mean
    m = a[..., 3] >= 0.95
    inner = m.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(m, dy, 0), dx, 1)
    d = (a[..., :3] - b[..., :3])[inner]
    interior = np.sqrt((d ** 2).mean()) / a[..., :3][inner].mean()
    return float(whole), float(interior)


def folder_bytes(path):
    return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))
