#!/usr/bin/python3
"""How much of a material's error over 8 x 8 pixel blocks is one scale over
the whole image, for drafts measured by real_drafts.py:

    lab/real_drafts/bias.py WORK/NAME...

For each: the mean of lookup-render over the cloth's pixels against the
reference's (seed 1; the cloth is where the reference differs from the
background), the median and 10th / 90th percentiles of that ratio over the
8 x 8 blocks wholly on the cloth, and the RMS of the blocks' difference over
the image's mean, before and after the one scale that fits the lookup to
the reference best (least squares over the cloth's blocks). Reads the
images cut to whole blocks that real_drafts.py leaves (*_crop8.exr).
"""
import os
import sys

import numpy as np

from means import BACKGROUND, blocks, load


def main():
    for d in sys.argv[1:]:
        ref = load(os.path.join(d, "ref_seed1_crop8.exr"))
        img = load(os.path.join(d, "lookup_crop8.exr"))
        cloth = np.abs(ref - BACKGROUND).sum(2) > 0.02
        r, t = blocks(ref), blocks(img)
        whole = blocks(cloth[..., None].astype(float))[..., 0] > 0.99
        ratio = t.sum(2)[whole] / r.sum(2)[whole]
        scale = (t[whole] * r[whole]).sum() / (t[whole] ** 2).sum()
        before = np.sqrt(((t - r) ** 2).mean()) / ref.mean()
        after = np.sqrt(((t * scale - r) ** 2).mean()) / ref.mean()
        p10, p90 = np.percentile(ratio, [10, 90])
        print(f"{os.path.basename(d.rstrip('/'))}: lookup / reference over the cloth "
              f"{img[cloth].mean() / ref[cloth].mean():.3f}, per block median "
              f"{np.median(ratio):.3f} ({p10:.3f} to {p90:.3f}); 8 x 8 RMS "
              f"{100 * before:.1f} %, {100 * after:.1f} % after a scale of {scale:.3f}")


if __name__ == "__main__":
    main()
