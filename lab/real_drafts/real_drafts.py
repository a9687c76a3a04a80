#!/usr/bin/python3
"""Every real WIF baked with `clothbake material` and no flags: the plan it
chose, its estimate against the process's own peak, its size and time, and
its error against its reference beside the reference's seed floor.

    lab/real_drafts/real_drafts.py CLOTHBAKE WORK [DRAFT.wif ...] [--bake-only]
    lab/real_drafts/real_drafts.py --table WORK

The scene is the paper scene's folds at 80 ends per UV (lab/common). Errors
are `clothbake compare`'s relative RMSE per pixel and over 8 x 8 pixel
blocks (of the image cut to whole blocks: 424 x 264); the seed floor is
the reference against the same cloth with generator seed 2, at the same
settings. Results go to WORK/NAME/results.json;
--table prints the guide's table from them. Re-running skips what is done.
"""
import argparse
import glob
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from paper_runs import ROOT, run, write_paper_scene  # noqa: E402

ENDS_PER_UV = 80
SPP = 64


def cropped(path, box):
    """The image cut to whole box x box blocks from its top-left corner (the
    paper scene's 426 x 266 to 424 x 264), beside it."""
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    out = path.replace(".exr", f"_crop{box}.exr")
    oiio.ImageBufAlgo.cut(buf, oiio.ROI(0, spec.width // box * box, 0,
                                        spec.height // box * box)).write(out)
    return out


def errors(exe, ref, img):
    out = {}
    for box in (1, 8):
        a, b = (ref, img) if box == 1 else (cropped(ref, box), cropped(img, box))
        cmd = [exe, "compare", a, b, "--json"] + (["--downsample", str(box)] if box > 1 else [])
        out["pixel" if box == 1 else "block8"] = json.loads(run(cmd)[1])["relative_rmse"]
    return out


def folder_bytes(path):
    return sum(os.path.getsize(os.path.join(path, f)) for f in os.listdir(path))


def save(d, res):
    with open(os.path.join(d, "results.json"), "w") as f:
        json.dump(res, f, indent=1)


def measure(exe, work, wif, bake_only):
    name = os.path.splitext(os.path.basename(wif))[0]
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "results.json")
    res = json.load(open(path)) if os.path.exists(path) else {"draft": os.path.basename(wif)}
    material = os.path.join(d, "material")
    if "bake" not in res:
        run([exe, "draft", wif, "-o", os.path.join(d, "draft")])
        draft = json.load(open(os.path.join(d, "draft", "draft.json")))
        res["threads"] = [draft["ends"], draft["picks"]]
        for seed in (1, 2):
            cloth = {"name": name, "weave": {"wif": os.path.abspath(wif)}, "seed": seed}
            cloth_path = os.path.join(d, f"cloth_seed{seed}.json")
            with open(cloth_path, "w") as f:
                json.dump(cloth, f, indent=1)
            per_uv = ENDS_PER_UV / draft["ends"]
            if seed == 1:
                write_paper_scene(cloth_path, per_uv, os.path.join(d, "scene.json"), False)
            write_paper_scene(cloth_path, per_uv, os.path.join(d, f"ref_seed{seed}.json"), True)
        scene = os.path.join(d, "scene.json")
        res["estimate"] = json.loads(run([exe, "material", scene, "-o", material,
                                          "--estimate"])[1])
        t, text = run([exe, "material", scene, "-o", material, "--quiet"])
        res["bake"] = json.loads(text.strip().splitlines()[-1])
        res["bake_wall_seconds"] = t
        res["bytes"] = folder_bytes(material)
        save(d, res)
        print(f"{name}: {res['bake']['plan']}; {t:.0f} s, peak "
              f"{res['bake']['peak_resident_bytes'] / 2**20:.0f} MiB", flush=True)
    if bake_only:
        return res
    for seed in (1, 2):
        ref = os.path.join(d, f"ref_seed{seed}.exr")
        if f"reference_seconds_seed{seed}" not in res:
            res[f"reference_seconds_seed{seed}"] = run(
                [exe, "render", os.path.join(d, f"ref_seed{seed}.json"), "-o", ref, "--spp",
                 str(SPP), "--quiet"])[0]
            save(d, res)
    if "material_error" not in res:
        img = os.path.join(d, "lookup.exr")
        run([exe, "lookup-render", os.path.join(d, "scene.json"), material, "-o", img, "--spp",
             str(SPP), "--quiet"])
        ref1 = os.path.join(d, "ref_seed1.exr")
        res["material_error"] = errors(exe, ref1, img)
        res["seed_floor"] = errors(exe, ref1, os.path.join(d, "ref_seed2.exr"))
        run([exe, "compare", ref1, img, "--sheet", os.path.join(d, "sheet.png")])
        save(d, res)
    print(f"{name}: material {res['material_error']}, floor {res['seed_floor']}", flush=True)
    return res


def table(work):
    rows = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(work, "*", "results.json")))]
    print("| draft | threads | chosen | folder | bake | peak memory (estimate) "
          "| error per pixel (seed floor) | over 8 x 8 pixels (floor) | reference |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "bake" not in r:
            continue
        b, e = r["bake"], r.get("estimate")
        mode = b["plan"].split(":")[0].replace("the whole repeat", "whole repeat")
        peak = b["peak_resident_bytes"]
        est = (f"{e['peak_bytes'] / 2**20:.0f}, {e['peak_bytes'] / peak:.2f} x" if e
               else "not run")
        cells = [r["draft"].removesuffix(".wif"), f"{r['threads'][0]} x {r['threads'][1]}", mode,
                 f"{r['bytes'] / 1e6:.0f} MB", f"{b['seconds']:.0f} s",
                 f"{peak / 2**20:.0f} MiB ({est})"]
        err, floor = r.get("material_error"), r.get("seed_floor")
        if err and floor:
            cells += [f"{100 * err['pixel']:.1f} % ({100 * floor['pixel']:.1f} %)",
                      f"{100 * err['block8']:.1f} % ({100 * floor['block8']:.1f} %)",
                      f"{r['reference_seconds_seed1']:.0f} s"]
        else:
            cells += ["not measured"] * 3
        print("| " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exe", nargs="?")
    ap.add_argument("work")
    ap.add_argument("drafts", nargs="*")
    ap.add_argument("--bake-only", action="store_true", help="the bakes alone, no references")
    ap.add_argument("--table", action="store_true", help="print the table from WORK")
    a = ap.parse_args()
    if a.table:
        table(a.work if a.exe is None else a.exe)
        return
    drafts = a.drafts or sorted(glob.glob(os.path.join(ROOT, "testscenes", "wif", "real",
                                                       "*.wif")))
    for wif in drafts:
        measure(a.exe, a.work, wif, a.bake_only)


if __name__ == "__main__":
    main()
