"""Images: an image's pixels, the relative RMSE of two, a still render of
the scene's camera, and a PNG of images side by side."""
import numpy as np


def pixels(path):
    """An image's pixels as float32 (H, W, channels), through OpenImageIO."""
    import OpenImageIO as oiio
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)


def rel_rmse(a, b, mask=None):
    """Relative RMSE of b against a over their RGB (the first three
    channels; an (n, 3) array of masked pixels works as well), optionally
    over a mask: RMSE / a's mean."""
    a, b = a[..., :3], b[..., :3]
    if mask is not None:
        a, b = a[mask], b[mask]
    return float(np.sqrt(((a - b) ** 2).mean()) / max(1e-12, a.mean()))


def render_still(path, seed=1):
    """Renders the scene's camera with Cycles' seed `seed`, saves the
    result to `path` (as the scene's output settings say) and returns its
    pixels."""
    import bpy
    scene = bpy.context.scene
    scene.cycles.seed = seed
    bpy.ops.render.render(write_still=False)
    bpy.data.images["Render Result"].save_render(path, scene=scene)
    return pixels(path)


def save_png(images, path):
    """The images side by side, their RGB clipped to [0, 1] and raised to
    1 / 2.2, as an 8-bit PNG at `path`."""
    import OpenImageIO as oiio
    row = np.concatenate([np.clip(i[..., :3], 0, 1) ** (1 / 2.2) for i in images], 1)
    buf = oiio.ImageBuf(oiio.ImageSpec(row.shape[1], row.shape[0], 3, oiio.UINT8))
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(row.astype(np.float32)))
    buf.write(path)
