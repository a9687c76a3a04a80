#!/usr/bin/python3
"""The cloth's mean and errors of images against a reference, for the bias
study (bias_sources.sh):

    lab/real_drafts/means.py REF.exr IMAGE.exr...

For each image: its mean over the cloth over the reference's (the cloth is
where the reference differs from the paper scene's background), the
relative RMSE per pixel and over 8 x 8 pixel blocks, and the 8 x 8 figure
after the one scale that fits the image to the reference best. Cuts the
images to whole blocks itself, so it takes any size.
"""
import os
import sys

import numpy as np
import OpenImageIO as oiio

BACKGROUND = np.array([0.05, 0.05, 0.06])  # the paper scene's


def load(path):
    return np.asarray(oiio.ImageBuf(path).get_pixels(oiio.FLOAT))[..., :3]


def blocks(a):
    h, w = a.shape[0] // 8 * 8, a.shape[1] // 8 * 8
    return a[:h, :w].reshape(h // 8, 8, w // 8, 8, -1).mean((1, 3))


def main():
    ref = load(sys.argv[1])
    cloth = np.abs(ref - BACKGROUND).sum(2) > 0.02
    for path in sys.argv[2:]:
        img = load(path)
        pixel = np.sqrt(((img - ref) ** 2).mean()) / ref.mean()
        block8 = np.sqrt(((blocks(img) - blocks(ref)) ** 2).mean()) / ref.mean()
        scale = (img[cloth] * ref[cloth]).sum() / (img[cloth] ** 2).sum()
        scaled = np.sqrt(((blocks(img) * scale - blocks(ref)) ** 2).mean()) / ref.mean()
        print(f"{os.path.basename(path)}: mean over the reference's "
              f"{img[cloth].mean() / ref[cloth].mean():.3f}; per pixel {100 * pixel:.1f} %, "
              f"8 x 8 {100 * block8:.1f} %, {100 * scaled:.1f} % after one scale")


if __name__ == "__main__":
    main()
