"""A render against a reference within its noise. A render's noise sigma
comes from two renders of it (two seeds: their relative RMSE d gives
sigma = d / sqrt(2)); a comparison passes when its relative RMSE is at
most 3 standard deviations of the difference, 3 hypot(sigma, the
reference's sigma), plus the systematic part the test states: at full
resolution and over 4 x 4 blocks (whose noise is sigma4)."""
import math

from lib.checks import check
from lib.images import rel_rmse


def blocks(image, k=4):
    """Means over k x k pixel blocks: the noise of independent pixels drops
    k times, a mistake larger than a few pixels stays."""
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, -1).mean((1, 3))


class Noisy:
    """A render and its noise: sigma = relative RMSE between two renders /
    spread, at full resolution and over 4 x 4 blocks."""

    def __init__(self, a, b, spread=math.sqrt(2.0)):
        """spread: the difference's standard deviation in units of one
        render's (sqrt(2) for two seeds of equal samples; sqrt(1.5) for
        Eevee's N against 2 N samples)."""
        self.image = a
        self.sigma = rel_rmse(a, b) / spread
        self.sigma4 = rel_rmse(blocks(a), blocks(b)) / spread


def within_noise(what, noisy, reference, systematic, ref_sigma=None):
    """Checks `noisy` against `reference` at full resolution and over 4 x 4
    blocks: relative RMSE <= 3 hypot(sigma, the reference's) + systematic,
    the reference's noise (sigma, sigma4) taken as the render's unless
    given. Returns [(error, bound)] for the pixels and the blocks."""
    out = []
    for label, a, b, sigma, rs in (
            ("pixels", reference, noisy.image, noisy.sigma,
             noisy.sigma if ref_sigma is None else ref_sigma[0]),
            ("4x4 blocks", blocks(reference), blocks(noisy.image), noisy.sigma4,
             noisy.sigma4 if ref_sigma is None else ref_sigma[1])):
        err = rel_rmse(a, b)
        bound = 3.0 * math.hypot(sigma, rs) + systematic
        check(err <= bound, f"{what}, {label}: relative RMSE {err:.4f} <= {bound:.4f} "
                            f"(noise {sigma:.4f}, reference's {rs:.4f}, systematic "
                            f"{systematic:.3f})")
        out.append((err, bound))
    return out
