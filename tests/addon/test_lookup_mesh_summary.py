"""The mesh summary a lookup records (docs/formats/lookup.md, objects[o].mesh):
the add-on computes the same numbers as clothbake (baker/core/geometry/mesh_summary.cpp)
and tells a moved vertex from an OBJ round trip."""
import math
import os
import subprocess

from clothbake.core import lookup_mesh_summary
from clothbake.core.lookup_manifest import read_manifest
from clothbake.core.obj import read_obj

# The two quads of tests/core/geometry/mesh_summary_test.cpp: a unit square and a
# square lifted at one corner.
POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0.5)]
UVS = [(0, 0), (0.5, 0), (0.5, 1), (0, 1), (1, 0), (1, 1)]
FACES = [(0, 1, 2, 3), (1, 4, 5, 2)]


def quads(positions=POSITIONS):
    return [([positions[i] for i in f], [UVS[i] for i in f]) for f in FACES]


def test_exact_on_two_quads():
    s = lookup_mesh_summary.summarize(quads())
    assert s["bounds_min"] == [0, 0, 0] and s["bounds_max"] == [2, 1, 0.5]
    assert s["uv_min"] == [0, 0] and s["uv_max"] == [1, 1]
    assert s["mean_centre"] == [1.0, 0.5, 0.0625]
    assert math.isclose(s["area"], 1 + math.sqrt(4.5) / 2, rel_tol=1e-12)


def test_round_trip_through_six_decimals_matches_and_a_moved_vertex_does_not():
    base = lookup_mesh_summary.summarize(quads())
    rounded = [tuple(float(f"{c + 1e-7 * (i + 1):.6f}") for c in p) for i, p in enumerate(POSITIONS)]
    assert lookup_mesh_summary.difference(base, lookup_mesh_summary.summarize(quads(rounded))) is None
    moved = list(POSITIONS)
    moved[1] = (1, 0.05, 0)  # an inner vertex, 5% of a quad's size: the bounds stay
    differs = lookup_mesh_summary.difference(base, lookup_mesh_summary.summarize(quads(moved)))
    assert differs is not None and "mean quad centre" in differs
    # The whole mesh moved: its bounds differ first.
    shifted = [(x + 0.01, y, z) for x, y, z in POSITIONS]
    assert "lower bounds" in lookup_mesh_summary.difference(base, lookup_mesh_summary.summarize(quads(shifted)))


def test_agrees_with_clothbakes_bake(clothbake_bin, source_dir, tmp_path):
    scene_dir = os.path.join(source_dir, "testscenes", "paper")
    out = tmp_path / "bake"
    subprocess.run([clothbake_bin, "bake", os.path.join(scene_dir, "scene.json"), "-o", str(out),
                    "--directions", "2", "--texels", "2", "--spp", "1", "--quads", "0-1", "--quiet"],
                   check=True, stdout=subprocess.DEVNULL)
    baked = read_manifest(out).objects[0].mesh
    mesh = read_obj(os.path.join(scene_dir, "cloth.obj"))
    ours = lookup_mesh_summary.summarize([([mesh.positions[i] for i in p], [mesh.uvs[i] for i in t])
                                   for p, t in mesh.quads])
    assert lookup_mesh_summary.difference(baked, ours) is None
    # Stricter than the tolerance: clothbake sums in double from float corners.
    for key in ("bounds_min", "bounds_max", "mean_centre"):
        assert math.dist(baked[key], ours[key]) < 1e-6
    assert math.isclose(baked["area"], ours["area"], rel_tol=1e-6)
