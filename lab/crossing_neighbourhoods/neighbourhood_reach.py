#!/usr/bin/env python3
"""How far a crossing's neighbourhood reaches into its appearance (issue 24,
"Shadows and grazing views reach further: measure how far").

    lab/crossing_neighbourhoods/neighbourhood_reach.py CLOTHBAKE WORK_DIR

Bakes, twice (seeds 1 and 2), an RGB material of a random 8 x 8 draft (seed 7,
every thread interlacing) in the paper cloth's yarns with the per-crossing
randomness taken out (density noise 0, shading variation 0, no ply twist), so
that two crossings whose surroundings are the same have the same texels up to
the bake's sampling noise: 64 texels (8 per thread), 8 view and 8 light
directions, 2 samples. From each, the radiance of every level-0 texel at
every front view node under (a) a uniform front hemisphere of light (the
light factors integrated as the Blender pack's world factors) and (b) one
light 70 degrees off the normal. Then, for every pair of crossings, the
relative RMS difference of their 8 x 8-texel blocks (per texel, and of the
blocks' means), averaged over the pairs of each kind:
  different plus-1    the crossings' plus-shaped stencils differ (the
                      crossing and its neighbours along its end and pick);
  same plus-1, 3 x 3  the stencil is the same, the 3 x 3 window not;
  same 3 x 3, 5 x 5   likewise one ring further;
  another seed        the same crossing in the two bakes: the floor.
by view band (z the view's cosine). A kind whose figure stands above the
floor is a neighbourhood that reaches into the crossing's appearance.
Prints the tables and writes WORK_DIR/reach.json.
"""
import itertools
import json
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "blender_addon"))
from clothbake.core import material_pack as mp  # noqa: E402
from clothbake.core.directions import hemi_oct_decode  # noqa: E402

TEXELS, K, KL, ENDS = 64, 8, 8, 8


def random_draft(seed=7, n=ENDS):
    rng = np.random.default_rng(seed)
    while True:
        d = rng.integers(0, 2, (n, n))
        if all(0 < r.sum() < n for r in d) and all(0 < c.sum() < n for c in d.T):
            return d


def bake(exe, spec, out, seed):
    if not os.path.isfile(os.path.join(out, "manifest.json")):
        subprocess.run([exe, "material", spec, "-o", out, "--texels", str(TEXELS),
                        "--directions", str(K), "--light-directions", str(KL), "--parts", "rgb",
                        "--no-view-parallax", "--seed", str(seed), "--quiet"], check=True,
                       stdout=subprocess.DEVNULL)


def radiance(folder):
    """{light: L[side, j, i, ty, tx, rgb]} of level 0, and the view nodes' z."""
    info = mp.read_material(folder)
    k, s, ranks = info.k, info.texels, info.max_rank
    px, names = mp._read_exr(os.path.join(folder, "level_0.exr"), "level 0")
    lf, lnames = mp._read_exr(os.path.join(folder, "light_factors.exr"), "light factors")
    c = np.stack([np.stack([px[..., names.index(f"k{r:04d}.{ch}")] for ch in "RGB"], -1)
                  for r in range(ranks)], 0)
    c = c.reshape(ranks, 2 * k, s, k, s, 3).transpose(1, 3, 0, 2, 4, 5)   # row, col, r, ty, tx
    f = np.stack([lf[..., lnames.index(f"k{r:04d}")] for r in range(ranks)], -1)
    graze = np.array([[np.sin(np.radians(70.0)), 0.0, np.cos(np.radians(70.0))]])
    lights = {"uniform": mp.world_weights(info.kl, info.light_map, samples=1 << 14)[0],
              "grazing70": mp.light_node_weights(graze, info.kl, info.light_map)[0]}
    out = {}
    for name, w in lights.items():
        per_view = np.einsum("n,vnr->vr", w, f).reshape(2, k, k, ranks)
        L = np.zeros((2, k, k, s, s, 3))
        for side, j, i in itertools.product(range(2), range(k), range(k)):
            L[side, j, i] = np.einsum("r,ryxc->yxc", per_view[side, j, i], c[side * k + j, i])
        out[name] = L
    z = np.array([[hemi_oct_decode(i / (k - 1), j / (k - 1))[2] for i in range(k)]
                  for j in range(k)])
    return out, z


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    exe, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    draft = random_draft()
    with open(os.path.join(ROOT, "testscenes", "paper", "cloth.json")) as fh:
        spec = json.load(fh)
    spec.update(name="random8", weave={"draft": draft.tolist()},
                resolution={"cells_per_thread": 8, "layers": 16, "supersample": 2})
    for family in ("warp", "weft"):
        spec[family]["twist_deg"] = 0
    spec["density"]["noise_amplitude"] = 0.0
    spec["shading"]["variation"] = 0.0
    spec_path = os.path.join(work, "random8.json")
    with open(spec_path, "w") as fh:
        json.dump(spec, fh, indent=1)
    bakes = []
    for seed in (1, 2):
        folder = os.path.join(work, f"seed{seed}")
        bake(exe, spec_path, folder, seed)
        bakes.append(radiance(folder))
    (a, z), (b, _) = bakes
    t = TEXELS // ENDS
    picks, ends = draft.shape

    def key(p, e, r, plus=False):
        if plus:
            return (tuple(draft[(p + d) % picks, e] for d in range(-r, r + 1)),
                    tuple(draft[p, (e + d) % ends] for d in range(-r, r + 1)))
        rows = [(p + d) % picks for d in range(-r, r + 1)]
        cols = [(e + d) % ends for d in range(-r, r + 1)]
        return draft[np.ix_(rows, cols)].tobytes()

    kinds = {
        "different plus-1": lambda c, d: key(*c, 1, True) != key(*d, 1, True),
        "same plus-1, different 3x3": lambda c, d: key(*c, 1, True) == key(*d, 1, True)
        and key(*c, 1) != key(*d, 1),
        "same 3x3, different 5x5": lambda c, d: key(*c, 1) == key(*d, 1) and key(*c, 2) != key(*d, 2),
    }
    bands = {"z > 0.7": z > 0.7, "0.3 < z <= 0.7": (z > 0.3) & (z <= 0.7), "z <= 0.3": z <= 0.3}
    crossings = [(p, e) for p in range(picks) for e in range(ends)]
    results = {}
    for mean in (False, True):
        def block(L, p, e):
            x = L[0][:, :, p * t:(p + 1) * t, e * t:(e + 1) * t]
            return np.broadcast_to(x.mean((2, 3), keepdims=True), x.shape) if mean else x
        what = "block means" if mean else "texels"
        for light in ("uniform", "grazing70"):
            L, Lb = a[light], b[light]
            print(f"== {what}, light {light}: relative RMS difference, by view band", flush=True)
            rows = {}
            for label, pred in list(kinds.items()) + [("another seed (floor)", None)]:
                pairs = [(c, c) for c in crossings] if pred is None else \
                    [(c, d) for c, d in itertools.combinations(crossings, 2) if pred(c, d)]
                if not pairs:
                    continue
                second = Lb if pred is None else L
                row = {}
                for band, m in bands.items():
                    scale = np.sqrt((L[0][m] ** 2).mean())
                    row[band] = float(np.mean([np.sqrt(((block(L, *c) - block(second, *d))[m] ** 2)
                                                       .mean()) for c, d in pairs]) / scale)
                rows[label] = dict(row, pairs=len(pairs))
                print(f"  {label:28s} ({len(pairs):4d} pairs): " +
                      ", ".join(f"{band} {v:.3f}" for band, v in row.items()), flush=True)
            results[f"{what}, {light}"] = rows
    with open(os.path.join(work, "reach.json"), "w") as fh:
        json.dump({"draft": draft.tolist(), "texels": TEXELS, "k": K, "kl": KL,
                   "results": results}, fh, indent=1)


if __name__ == "__main__":
    main()
