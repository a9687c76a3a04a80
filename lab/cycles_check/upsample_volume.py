#!/usr/bin/python3
"""Splits every voxel of a tiled volume (lab/common/tile_volume.py) into N^3
voxels of the same value: the same piecewise-constant density as clothbake's
nearest-cell lookup, on a grid N times finer, so that Cycles' trilinear
lookup blurs it over 1/N of a cell instead of a whole cell. An experiment of
docs/design/results.md ("An independent check: Cycles real volumes"): how much of
the difference between Cycles and clothbake is the lookup filter.

Usage: upsample_volume.py TILED.vdb VOLUME_DIR N OUT_DIR
Writes OUT_DIR/tiled.vdb (the `density` grid only, voxel (i, j, k) centred at
((i+.5) d/N, ...) as clothbake's) and OUT_DIR/volume.json (VOLUME_DIR's, with
`cells` multiplied by N, which lab/common/volume_render.py reads for the
voxel size of its half-voxel shift).
"""
import json
import os
import sys

import numpy as np
import pyopenvdb as vdb

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from tile_volume import densify  # noqa: E402


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    tiled, vdir, n, out_dir = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(vdir, "volume.json")) as f:
        meta = json.load(f)
    g = vdb.read(tiled, "density")
    (i0, j0, k0), (i1, j1, k1) = g.evalActiveVoxelBoundingBox()
    a = np.zeros((i1 + 1, j1 + 1, k1 + 1), np.float32)
    g.copyToArray(a, ijk=(0, 0, 0))
    fine = np.ascontiguousarray(a.repeat(n, 0).repeat(n, 1).repeat(n, 2))
    t = vdb.FloatGrid(-1.0)
    t.copyFromArray(fine, ijk=(0, 0, 0), tolerance=0.0)
    t.background = 0.0
    densify(t, lambda v: v + 1.0)
    t.name = "density"
    t.gridClass = vdb.GridClass.FOG_VOLUME
    d = [s / c / n for s, c in zip(meta["size_mm"], meta["cells"])]
    m = [[d[0], 0, 0, 0], [0, d[1], 0, 0], [0, 0, d[2], 0], [d[0] / 2, d[1] / 2, d[2] / 2, 1]]
    t.transform = vdb.createLinearTransform(m)
    if t.activeLeafVoxelCount() != fine.size:
        sys.exit("upsample_volume.py: %d leaf voxels, expected %d" % (t.activeLeafVoxelCount(), fine.size))
    vdb.write(os.path.join(out_dir, "tiled.vdb"), grids=[t])
    meta["cells"] = [c * n for c in meta["cells"]]
    meta["upsampled_from"] = os.path.abspath(tiled)
    with open(os.path.join(out_dir, "volume.json"), "w") as f:
        json.dump(meta, f, indent=2)
    print("upsample_volume: %d x %d x %d voxels" % fine.shape)


if __name__ == "__main__":
    main()
