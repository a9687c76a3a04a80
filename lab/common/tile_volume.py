#!/usr/bin/python3
"""Tiles one weave repeat of `clothbake volume` (DIR/volume.vdb) over a flat
scene's cloth: writes OUT.vdb with the grids `density` and `diffuse`
repeated nu x nv times along x and y (nu, nv from the scene: repeats_per_uv x
the patch's UV extent), in the same texture-mm space and voxel transform
(voxel (i, j, k) centred at ((i+.5)dx, (j+.5)dy, (k+.5)dz) mm).

Why one tiled grid rather than nu x nv Volume objects sharing one datablock:
Cycles interpolates voxels trilinearly inside one grid; at the border of a
grid it blends with the empty background, so abutting objects would show a
seam every repeat (and Cycles would build and walk nu x nv volume bounds).
One grid keeps the repeat periodic, as clothbake's texture is. The cost is
memory: nu nv times the voxels (6 x 6 x 64 x 64 x 16 = 2.4 M here).

Every voxel is written active and as a leaf voxel (as clothbake does:
Blender 3.4 renders a constant *tile* as empty). pyopenvdb's copyFromArray
prunes a constant 8^3 block into a tile: it is given a background of -1 that
no voxel has (so blocks equal to the background are not dropped) and the
background is set to 0 afterwards; blocks of one constant value still become
active tiles (every block of a uniform slab, the empty blocks of a weave),
and densify() turns each back into a leaf of voxels. The script fails if any
active voxel is left in a tile.

Usage: tile_volume.py SCENE.json VOLUME_DIR OUT.vdb
"""
import json
import os
import sys
import time

import numpy as np
import pyopenvdb as vdb

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import flat_volume  # noqa: E402


def densify(grid, bump):
    """Replaces every active tile by leaf nodes holding its value.

    OpenVDB leaves an active tile alone when a voxel in it is set to the
    tile's own value, so one voxel per 8^3 leaf is set to value + bump first
    (which splits the tile down to a leaf filled with the tile's value) and
    then back."""
    acc = grid.getAccessor()
    tiles = [(t.min, t.max, t.value) for t in grid.iterOnValues() if t.count > 1]
    for lo, hi, value in tiles:
        other = bump(value)
        for i in range(lo[0], hi[0] + 1, 8):
            for j in range(lo[1], hi[1] + 1, 8):
                for k in range(lo[2], hi[2] + 1, 8):
                    acc.setValueOn((i, j, k), other)
                    acc.setValueOn((i, j, k), value)


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: tile_volume.py SCENE.json VOLUME_DIR OUT.vdb")
    scene, vdir, out = sys.argv[1:]
    t0 = time.perf_counter()
    with open(os.path.join(vdir, "volume.json")) as f:
        meta = json.load(f)
    lay = flat_volume.layout(scene, meta["size_mm"])
    nu, nv = lay["repeats"]
    grids, file_meta = vdb.readAll(os.path.join(vdir, "volume.vdb"))
    cells = meta["cells"]
    out_grids = []
    stats = {}
    for g in grids:
        if g.name not in ("density", "diffuse"):
            continue
        shape = tuple(cells) + ((3,) if g.valueTypeName == "vec3s" else ())
        a = np.zeros(shape, np.float32)
        g.copyToArray(a, ijk=(0, 0, 0))
        reps = (nu, nv, 1) + ((1,) if a.ndim == 4 else ())
        tiled = np.ascontiguousarray(np.tile(a, reps))
        if g.valueTypeName == "vec3s":
            t = vdb.Vec3SGrid((-1.0, -1.0, -1.0))
            t.copyFromArray(tiled, ijk=(0, 0, 0), tolerance=(0.0, 0.0, 0.0))
            t.background = (0.0, 0.0, 0.0)
            densify(t, lambda v: tuple(x + 1.0 for x in v))
        else:
            t = vdb.FloatGrid(-1.0)
            t.copyFromArray(tiled, ijk=(0, 0, 0), tolerance=0.0)
            t.background = 0.0
            densify(t, lambda v: v + 1.0)
        t.name = g.name
        t.transform = g.transform
        if g.name == "density":
            t.gridClass = vdb.GridClass.FOG_VOLUME
        active, leaf = t.activeVoxelCount(), t.activeLeafVoxelCount()
        stats[g.name] = {"active": active, "in_leaves": leaf, "in_tiles": active - leaf,
                         "index_box": [list(c) for c in t.evalActiveVoxelBoundingBox()]}
        if active != tiled.shape[0] * tiled.shape[1] * tiled.shape[2]:
            sys.exit("tile_volume.py: %s: %d active voxels, expected %d"
                     % (g.name, active, tiled[..., 0].size if a.ndim == 4 else tiled.size))
        if leaf != active:
            sys.exit("tile_volume.py: %s: %d active voxels in tiles" % (g.name, active - leaf))
        out_grids.append(t)
    file_meta = dict(file_meta)
    file_meta["clothbake_tiled"] = "%d x %d repeats" % (nu, nv)
    vdb.write(out, grids=out_grids, metadata=file_meta)
    info = {"repeats": [nu, nv], "grids": stats, "seconds": time.perf_counter() - t0,
            "bytes": os.path.getsize(out)}
    print("tile_volume: " + json.dumps(info))
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(info, f, indent=2)


if __name__ == "__main__":
    main()
