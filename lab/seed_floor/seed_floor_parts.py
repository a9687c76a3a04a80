#!/usr/bin/env python3
"""Which of the cloth's random draws make a draft's seed floor
(docs/design/material.md, "The per-pixel floor"):

    lab/seed_floor/seed_floor_parts.py CLOTHBAKE WORK_DIR DRAFT.wif

On the paper scene's folds, camera and lights at 80 warp ends per UV (the
references of addressed_drafts.py: 64 spp, a quarter of the march step, no
light roulette), renders the cloth with generator seed 1 and seed 2 and
compares the two, once with every random draw of the generator on, once
with each alone, once with none; and once the same cloth with another
render seed (the Monte Carlo noise of two 64-spp renders alone). The error
is `clothbake compare`'s relative RMSE per pixel and after a 2 x 2
box. Writes WORK_DIR/floor_parts.json.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from paper_runs import run, write_paper_scene  # noqa: E402
ENDS_PER_UV = 80

# The generator's random draws (cloth_spec.h) and the spec fields that turn
# each off.
OFF = {
    "noise": lambda s: s.setdefault("density", {}).update(noise_amplitude=0.0),
    "variation": lambda s: s.setdefault("shading", {}).update(variation=0.0),
    "twist": lambda s: [s.setdefault(f, {}).update(twist_deg=0.0) for f in ("warp", "weft")],
    "spread": lambda s: s.update(angle_spread_deg=0.0),
}


def compare(exe, a, b):
    out = {}
    for box in (1, 2):
        cmd = [exe, "compare", a, b, "--json"] + (["--downsample", str(box)] if box > 1 else [])
        out[f"box{box}"] = json.loads(run(cmd)[1])["relative_rmse"]
    return out


def render(exe, d, key, spec, ends, render_seed=7):
    img = os.path.join(d, f"{key}.exr")
    if os.path.exists(img):
        return img
    cloth = os.path.join(d, f"{key}_cloth.json")
    with open(cloth, "w") as f:
        json.dump(spec, f, indent=1)
    scene = write_paper_scene(cloth, ENDS_PER_UV / ends, os.path.join(d, f"{key}.json"), True)
    if render_seed != 7:
        s = json.load(open(scene))
        s["render"]["seed"] = render_seed
        with open(scene, "w") as f:
            json.dump(s, f, indent=1)
    t, _ = run([exe, "render", scene, "-o", img, "--spp", "64", "--quiet"])
    print(f"{key}: {t:.0f} s", flush=True)
    return img


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("clothbake")
    ap.add_argument("work")
    ap.add_argument("wif")
    a = ap.parse_args()
    exe = os.path.abspath(a.clothbake)
    name = os.path.splitext(os.path.basename(a.wif))[0]
    d = os.path.join(a.work, name)
    os.makedirs(d, exist_ok=True)
    run([exe, "draft", a.wif, "-o", os.path.join(d, "draft")])
    ends = json.load(open(os.path.join(d, "draft", "draft.json")))["ends"]
    base = {"name": name, "weave": {"wif": os.path.abspath(a.wif)}}

    def spec(seed, keep):
        s = json.loads(json.dumps(base))
        s["seed"] = seed
        for part, off in OFF.items():
            if part not in keep:
                off(s)
        return s

    res = {"draft": os.path.basename(a.wif)}
    everything = set(OFF)
    one = render(exe, d, "all_seed1", spec(1, everything), ends)
    res["monte_carlo"] = compare(exe, one, render(exe, d, "all_seed1_render8",
                                                    spec(1, everything), ends, 8))
    print("monte_carlo", res["monte_carlo"], flush=True)
    res["all"] = compare(exe, one, render(exe, d, "all_seed2", spec(2, everything), ends))
    print("all", res["all"], flush=True)
    for case, keep in [("none", set())] + [(p, {p}) for p in OFF]:
        res[case] = compare(exe, render(exe, d, f"{case}_seed1", spec(1, keep), ends),
                            render(exe, d, f"{case}_seed2", spec(2, keep), ends))
        print(case, res[case], flush=True)
    with open(os.path.join(d, "floor_parts.json"), "w") as f:
        json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
