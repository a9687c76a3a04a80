"""Check, inside Blender 3.4, that clothbake's volume.vdb loads with the
expected grids, voxel counts and extents, and that Cycles renders its voxels.

Run by run_vdb_load.sh:
  blender -b --factory-startup --python-exit-code 1 -P vdb_load.py -- \
      VOLUME.vdb VOLUME.json RENDER.exr

Checks (every failure is listed; any failure makes Blender exit with 1):
 1. Blender: the grid names are exactly the five clothbake writes, with the
    data_type names Blender 3.4 uses (FLOAT, VECTOR_FLOAT); every grid loads;
    each grid's index-to-object matrix puts voxel (i,j,k)'s centre at
    ((i+.5)dx, (j+.5)dy, (k+.5)dz) with d = size_mm / cells.
 2. Voxel counts. Blender's Python API has no voxel count; what it exposes is
    the object's bound_box, which Blender 3.4 computes from the *centres* of
    the active voxels of all grids: [d/2, size - d/2] on each axis, i.e. the
    box [0, size] shrunk by exactly half a voxel per side. We assert that to
    1e-3 voxel and derive the number of voxel centres spanned per axis.
    pyopenvdb (Debian's python3-openvdb) reads the same file and gives, per
    grid, activeVoxelCount() == nx*ny*nz, activeLeafVoxelCount() equal to it,
    no active tile (iterOnValues() item with count > 1) and the active index
    box (0,0,0)..(nx-1,ny-1,nz-1). Bounds cannot see tiles (a tile counts in
    the bounding box), hence both.
 3. Cycles CPU renders (64 x 64, 16 spp, fixed seed, transparent film,
    Principled Volume reading `density`, multiplier DENSITY_SCALE, white
    world + sun):
    a. RENDER.exr: orthographic camera looking down at the cloth centre,
       60 deg off vertical. Seen straight down, the centre is a see-through
       gap crossing (see c); at 60 deg its ray crosses yarns. Centre 2 x 2
       pixels alpha > 0.5 each; mean alpha > 0.9 x the opacity predicted by
       marching each pixel's ray through the pyopenvdb density (nearest
       voxel; the 10 % margin covers nearest-vs-interpolated lookup and
       Monte Carlo noise); alpha correlates (> 0.85) with that prediction.
    b. RENDER_control.exr: same, density multiplier 0: alpha must be 0
       everywhere (shows the checks in (a) can fail).
    c. RENDER_top.exr: straight down, one pixel per voxel column, pixel
       filter 0.01 px. The alpha image must correlate (> 0.85) with the
       opacity 1 - exp(-DENSITY_SCALE * sum_k density * dz) pyopenvdb
       predicts per column, unshifted or shifted by half a voxel (Blender
       3.4 places voxel i's value at index i + 0.5); this shows Blender sees
       these voxels, including the see-through gaps where yarn gaps cross
       (the vertical view of the volume centre is such a gap, hence (a) is
       oblique).
"""
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, failures  # noqa: E402

EXPECTED_TYPES = {
    "density": "FLOAT",
    "specular": "FLOAT",
    "exponent": "FLOAT",
    "tangent": "VECTOR_FLOAT",
    "diffuse": "VECTOR_FLOAT",
}
PYOPENVDB_TYPES = {"FLOAT": "float", "VECTOR_FLOAT": "vec3s"}
DENSITY_SCALE = 100.0  # per Blender unit; the VDB's unit (mm) is one Blender unit
RES = 64
SAMPLES = 16
TILT_DEG, AZIMUTH_DEG, OBLIQUE_SCALE = 60.0, 30.0, 0.6

def fatal(what):
    raise RuntimeError("vdb_load.py: " + what)


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 3:
        fatal("usage: blender -b -P vdb_load.py -- VOLUME.vdb VOLUME.json RENDER.exr")
    return argv


# --------------------------------------------------------------------------
# 1. Grids as Blender loads them
def blender_grids(vdb_path, cells, size):
    vol = bpy.data.volumes.new("cloth")
    vol.filepath = vdb_path
    if not vol.grids.load():
        fatal("Blender could not load %s: %s" % (vdb_path, vol.grids.error_message))
    types = {g.name: g.data_type for g in vol.grids}
    print("Blender grids: %s" % ", ".join("%s=%s" % kv for kv in sorted(types.items())))
    check(set(types) == set(EXPECTED_TYPES),
          "Blender grid names %s == %s" % (sorted(types), sorted(EXPECTED_TYPES)))
    for name, want in sorted(EXPECTED_TYPES.items()):
        if name in types:
            check(types[name] == want, "Blender grid %s data_type %s == %s" % (name, types[name], want))
    d = [s / n for s, n in zip(size, cells)]
    for g in vol.grids:
        # load() says whether the voxels were read. is_loaded stays True
        # after it on 3.4 only: 4.3 and 5.2 keep grids in a shared cache and
        # report False there (the bounds below need the voxels either way).
        check(g.load() and (g.is_loaded or bpy.app.version >= (4, 0, 0)),
              "Blender loads voxels of grid %s" % g.name)
        m = g.matrix_object
        err = max(abs(m[r][c] - (d[r] if r == c else 0.0)) for r in range(3) for c in range(3))
        err = max([err] + [abs(m[r][3] - d[r] / 2) for r in range(3)])
        check(err < 1e-6, "grid %s index-to-object: scale d, offset d/2 (max error %.1e)" % (g.name, err))
    return vol


# 2a. Extents Blender loaded
def blender_bounds(ob, cells, size):
    bpy.context.view_layer.update()
    corners = [tuple(c) for c in ob.bound_box]
    lo = [min(c[a] for c in corners) for a in range(3)]
    hi = [max(c[a] for c in corners) for a in range(3)]
    counts = []
    for a, axis in enumerate("xyz"):
        d = size[a] / cells[a]
        err = max(abs(lo[a] - d / 2), abs(hi[a] - (size[a] - d / 2))) / d
        spanned = (hi[a] - lo[a]) / d + 1
        counts.append(round(spanned))
        print("Blender bound_box %s: [%.6f, %.6f] mm, voxel %.6f mm; "
              "+/- half a voxel gives [%.6f, %.6f], size_mm %.6f; %.4f voxel centres"
              % (axis, lo[a], hi[a], d, lo[a] - d / 2, hi[a] + d / 2, size[a], spanned))
        check(err < 1e-3, "bound_box %s == [d/2, size - d/2] (error %.1e voxel, tolerance 1e-3)"
              % (axis, err))
    n = counts[0] * counts[1] * counts[2]
    check(counts == list(cells) and n == math.prod(cells),
          "voxel centres spanned by Blender's bounds %s = %d == %d" % (counts, n, math.prod(cells)))


# 2b. Active voxels per grid, read with pyopenvdb
def openvdb_counts(vdb_path, cells, size):
    try:
        import pyopenvdb
    except ImportError as e:
        fatal("pyopenvdb does not import inside Blender (apt install python3-openvdb): %s" % e)
    grids, _ = pyopenvdb.readAll(vdb_path)
    want = math.prod(cells)
    box = ((0, 0, 0), tuple(n - 1 for n in cells))
    check(sorted(g.name for g in grids) == sorted(EXPECTED_TYPES),
          "pyopenvdb grid names %s" % sorted(g.name for g in grids))
    density = None
    for g in grids:
        active, leaf = g.activeVoxelCount(), g.activeLeafVoxelCount()
        tiles = sum(1 for it in g.iterOnValues() if it.count > 1)
        bbox = tuple(tuple(c) for c in g.evalActiveVoxelBoundingBox())
        vsize = g.transform.voxelSize()
        print("pyopenvdb %-8s %-5s active %d, in leaves %d, active tiles %d, index box %s, voxel %s"
              % (g.name, g.valueTypeName, active, leaf, tiles, bbox,
                 tuple(round(v, 6) for v in vsize)))
        want_type = PYOPENVDB_TYPES.get(EXPECTED_TYPES.get(g.name))
        check(g.valueTypeName == want_type, "%s value type %s == %s" % (g.name, g.valueTypeName, want_type))
        check(active == want, "%s activeVoxelCount %d == nx*ny*nz %d" % (g.name, active, want))
        check(leaf == active and tiles == 0,
              "%s has no active tiles (%d tiles, %d voxels outside leaves)" % (g.name, tiles, active - leaf))
        check(bbox == box, "%s active index box %s == %s" % (g.name, bbox, box))
        check(all(abs(v - s / n) < 1e-6 for v, s, n in zip(vsize, size, cells)),
              "%s voxel size == size_mm / cells" % g.name)
        if g.name == "density":
            density = np.zeros(cells, np.float32)
            g.copyToArray(density, ijk=(0, 0, 0))
    if density is None:
        fatal("no density grid to predict the render from")
    return density


# --------------------------------------------------------------------------
# 3. Rendering
def setup_scene(ob, size):
    sc = bpy.context.scene
    mat = bpy.data.materials.new("cloth_volume")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    pv = nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density Attribute"].default_value = "density"
    out = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(pv.outputs["Volume"], out.inputs["Volume"])
    ob.data.materials.append(mat)

    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    sc.world = world
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(30), 0, math.radians(20))
    sc.collection.objects.link(sun)

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.type = "ORTHO"
    cam.data.sensor_fit = "HORIZONTAL"
    sc.collection.objects.link(cam)
    sc.camera = cam

    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = SAMPLES
    sc.cycles.seed = 0
    sc.cycles.use_adaptive_sampling = False
    sc.cycles.use_denoising = False
    sc.render.film_transparent = True
    sc.render.resolution_percentage = 100
    s = sc.render.image_settings
    s.file_format, s.color_mode, s.color_depth = "OPEN_EXR", "RGBA", "32"
    return pv, cam.data, cam


def predict_ortho(density, size, cam, scale, w, h, shift):
    """Opacity per pixel (rows bottom-up) of an orthographic camera, by
    marching each pixel's ray through the density voxels (nearest voxel;
    shift 0.5 samples the voxel half a voxel back, as Blender 3.4 shows it)."""
    m = np.array(cam.matrix_world)
    rx, ry, fwd, org = m[:3, 0], m[:3, 1], -m[:3, 2], m[:3, 3]
    x = ((np.arange(w) + 0.5) / w - 0.5) * scale
    y = ((np.arange(h) + 0.5) / h - 0.5) * scale * h / w
    o = org + y[:, None, None] * ry + x[None, :, None] * rx  # [h, w, 3]
    size = np.array(size)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_a = (0.0 - o) / fwd
        t_b = (size - o) / fwd
    t0 = np.nanmax(np.minimum(t_a, t_b), axis=2)
    t1 = np.nanmin(np.maximum(t_a, t_b), axis=2)
    length = np.maximum(t1 - t0, 0.0)
    cells = np.array(density.shape)
    steps = 4 * int(cells.max())
    u = (np.arange(steps) + 0.5) / steps
    tau = np.zeros((h, w))
    for s in u:
        p = o + (t0 + s * length)[..., None] * fwd
        i = np.floor(p / size * cells - shift).astype(int)
        ok = np.all((i >= 0) & (i < cells), axis=2)
        i = np.where(ok[..., None], i, 0)
        tau += np.where(ok, density[i[..., 0], i[..., 1], i[..., 2]], 0.0)
    return 1.0 - np.exp(-DENSITY_SCALE * tau * length / steps)


def fmt(a):
    return "[" + " ".join("%.3f" % v for v in np.ravel(a)) + "]"


def correlation(a, b):
    """Pearson correlation; 0 when either image is constant (e.g. empty)."""
    if a.std() == 0 or b.std() == 0:
        return 0.0
    return float(np.corrcoef(a.ravel(), b.ravel())[0, 1])


def render(path):
    sc = bpy.context.scene
    sc.render.filepath = path
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - t0
    if not os.path.isfile(path):
        fatal("Cycles wrote no %s" % path)
    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    px = np.empty(w * h * img.channels, np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    px = px.reshape(h, w, -1)  # rows bottom-up
    return px[..., 3], px[..., :3], seconds


def main():
    vdb_path, json_path, exr_path = args()
    t_start = time.time()
    with open(json_path) as f:
        meta = json.load(f)
    cells = [int(n) for n in meta["cells"]]
    size = [float(s) for s in meta["size_mm"]]
    print("volume.json: cells %s, size_mm %s" % (cells, size))

    for o in list(bpy.data.objects):  # factory start-up cube, camera, light
        bpy.data.objects.remove(o)
    vol = blender_grids(vdb_path, cells, size)
    ob = bpy.data.objects.new("cloth", vol)
    bpy.context.scene.collection.objects.link(ob)
    blender_bounds(ob, cells, size)
    density = openvdb_counts(vdb_path, cells, size)

    dz = size[2] / cells[2]
    col_alpha = 1.0 - np.exp(-DENSITY_SCALE * density.sum(axis=2) * dz)  # [i, j]
    predicted_mean = float(col_alpha.mean())
    print("pyopenvdb prediction, vertical rays, density x %g: mean opacity %.4f, "
          "%d of %d columns see-through (opacity < 0.5)"
          % (DENSITY_SCALE, predicted_mean, int((col_alpha < 0.5).sum()), col_alpha.size))

    pv, camera, cam = setup_scene(ob, size)
    sc = bpy.context.scene
    centre = Vector([s / 2 for s in size])
    base, ext = os.path.splitext(exr_path)

    # (a) oblique view of the centre
    tilt, az = math.radians(TILT_DEG), math.radians(AZIMUTH_DEG)
    view = Vector((math.sin(tilt) * math.sin(az), -math.sin(tilt) * math.cos(az), math.cos(tilt)))
    cam.location = centre + 10 * max(size) * view
    cam.rotation_euler = (tilt, 0.0, az)
    camera.ortho_scale = OBLIQUE_SCALE * max(size)
    camera.clip_end = 100 * max(size)
    sc.render.resolution_x = sc.render.resolution_y = RES
    sc.cycles.filter_width = 1.5
    bpy.context.view_layer.update()
    pred = {sh: predict_ortho(density, size, cam, camera.ortho_scale, RES, RES, sh) for sh in (0.0, 0.5)}
    pv.inputs["Density"].default_value = DENSITY_SCALE
    alpha, rgb, sec = render(exr_path)
    mid = slice(RES // 2 - 1, RES // 2 + 1)
    c = alpha[mid, mid]
    pmean = min(float(p.mean()) for p in pred.values())
    bound = 0.9 * pmean
    print("render %s: %.1f s; oblique; centre 2x2 alpha %s (predicted %s); mean alpha %.4f "
          "(predicted %s); mean RGB %s"
          % (os.path.basename(exr_path), sec, fmt(c), fmt(pred[0.0][mid, mid]), alpha.mean(),
             ", ".join("%.4f" % p.mean() for p in pred.values()),
             " ".join("%.3f" % v for v in rgb.reshape(-1, 3).mean(0))))
    corr_ob = [correlation(alpha, p) for p in pred.values()]
    print("oblique alpha vs pyopenvdb ray-marched opacity: correlation unshifted %.4f, "
          "half-voxel shifted %.4f" % tuple(corr_ob))
    check(c.min() > 0.5, "oblique render centre alpha %.3f > 0.5" % c.min())
    check(alpha.mean() > bound, "oblique render mean alpha %.4f > 0.9 x predicted %.4f = %.4f"
          % (alpha.mean(), pmean, bound))
    check(max(corr_ob) > 0.85, "oblique alpha correlates with the ray-marched voxels (%.4f > 0.85)"
          % max(corr_ob))

    # (b) control: same view, density multiplier 0
    pv.inputs["Density"].default_value = 0.0
    alpha0, _, sec = render(base + "_control" + ext)
    print("render %s: %.1f s; density x 0; max alpha %g" % (os.path.basename(base + "_control" + ext), sec, alpha0.max()))
    check(alpha0.max() == 0.0, "control render (density x 0) fully transparent, max alpha %g" % alpha0.max())

    # (c) straight down, one pixel per voxel column
    pv.inputs["Density"].default_value = DENSITY_SCALE
    dx, dy = size[0] / cells[0], size[1] / cells[1]
    if abs(dx - dy) > 1e-6 * dx:
        fatal("top view needs square voxel columns, got %g x %g mm" % (dx, dy))
    cam.location = centre + Vector((0, 0, 10 * max(size)))
    cam.rotation_euler = (0.0, 0.0, 0.0)
    camera.ortho_scale = size[0]
    sc.render.resolution_x, sc.render.resolution_y = cells[0], cells[1]
    sc.cycles.filter_width = 0.01
    top_path = base + "_top" + ext
    top, _, sec = render(top_path)
    top = top.T  # [i, j]: image x is world +x, image up is world +y
    tau = DENSITY_SCALE * density.sum(axis=2) * dz
    t = np.pad(tau, ((1, 0), (1, 0)), mode="edge")
    shifted = 1.0 - np.exp(-0.25 * (t[:-1, :-1] + t[1:, :-1] + t[:-1, 1:] + t[1:, 1:]))
    corr = {name: correlation(top, p) for name, p in (("unshifted", col_alpha), ("half-voxel shifted", shifted))}
    print("render %s: %.1f s; top view; mean alpha %.4f (predicted %.4f); %d pixels alpha < 0.5 "
          "(predicted %d unshifted, %d shifted); centre 2x2 alpha %s"
          % (os.path.basename(top_path), sec, top.mean(), predicted_mean, int((top < 0.5).sum()),
             int((col_alpha < 0.5).sum()), int((shifted < 0.5).sum()),
             fmt(top[cells[0] // 2 - 1:cells[0] // 2 + 1, cells[1] // 2 - 1:cells[1] // 2 + 1])))
    print("top view alpha vs pyopenvdb per-column opacity: correlation %s"
          % ", ".join("%s %.4f" % kv for kv in corr.items()))
    check(max(corr.values()) > 0.85, "top view alpha correlates with the voxel columns (%.4f > 0.85)"
          % max(corr.values()))
    check(abs(top.mean() - predicted_mean) < 0.05, "top view mean alpha %.4f within 0.05 of predicted %.4f"
          % (top.mean(), predicted_mean))

    print("vdb_load.py: %d checks failed; %.1f s in Blender" % (len(failures), time.time() - t_start))
    if failures:
        fatal("%d check(s) failed:\n  " % len(failures) + "\n  ".join(failures))


main()
