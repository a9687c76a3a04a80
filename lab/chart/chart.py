"""Speed against accuracy: sweeps clothbake's methods and settings on one
scene, measures each point's seconds (median of several runs) and its error
against a converged reference of the same scene, and writes a CSV and a
log-log chart (error against seconds, one series per method, the Pareto
front marked) as PNG and SVG. Driven by lab/chart/chart.sh; docs/design/results.md
shows the results.

    /usr/bin/python3 lab/chart/chart.py SCENE.json --name NAME --out DIR
        [--scale S] [--runs N] [--ref-spp N] [--volume-route CMD]

What a point's seconds are: the wall time of the command a user runs to get
the image (clothbake render / lookup-render, or Blender's render of the
scene), program start-up and image writing included; for bake-based paths a
second figure adds the bake's own seconds (a bake is reused across renders
of one scene, so both matter). Errors: relative RMSE and PSNR over RGB
(the reference's maximum as peak) from `clothbake compare`, against a
render of the same scene at --ref-spp samples per pixel and a quarter of the
scene's march step.
"""
import argparse
import csv
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))  # lab/chart/ -> the repository


def log(msg):
    print(f"[chart] {msg}", file=sys.stderr, flush=True)


class Runner:
    def __init__(self, exe, blender, out):
        self.exe = exe
        self.blender = blender
        self.out = out

    def timed(self, cmd, env=None):
        start = time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              env=env)
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed:\n{proc.stderr[-2000:]}")
        return seconds, proc.stdout

    def compare(self, reference, image):
        _, out = self.timed([self.exe, "compare", reference, image, "--json"])
        j = json.loads(out)
        return j["relative_rmse"], j["psnr"]


def write_scene(base, path, scale, render_overrides=None):
    """A copy of the scene with absolute paths, the resolution scaled and
    render settings overridden."""
    folder = os.path.dirname(os.path.abspath(base["__path__"]))
    scene = json.loads(json.dumps({k: v for k, v in base.items() if k != "__path__"}))
    for obj in scene["objects"]:
        obj["mesh"] = os.path.normpath(os.path.join(folder, obj["mesh"]))
        if isinstance(obj["cloth"], str):
            obj["cloth"] = os.path.normpath(os.path.join(folder, obj["cloth"]))
    cam = scene["camera"]
    cam["resolution"] = [max(8, round(v * scale)) for v in cam.get("resolution", [426, 266])]
    scene.setdefault("render", {}).update(render_overrides or {})
    with open(path, "w") as f:
        json.dump(scene, f, indent=2)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--name", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scale", type=float, default=1.0, help="resolution scale of the sweep")
    ap.add_argument("--runs", type=int, default=3, help="runs per point (median)")
    ap.add_argument("--ref-spp", type=int, default=256)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "baker", "clothbake"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--quick", action="store_true", help="fewer points (smoke test)")
    ap.add_argument("--extra-points", help="CSV of points rendered elsewhere: series, label, "
                    "seconds, image")
    args = ap.parse_args()

    os.makedirs(args.out, exist_ok=True)
    with open(args.scene) as f:
        base = json.load(f)
    base["__path__"] = args.scene
    render = base.get("render", {})
    step = float(render.get("step_cells", 0.5))
    spp = int(render.get("spp", 4))
    isotropic = render.get("shading") == "isotropic"
    r = Runner(args.exe, args.blender, args.out)
    rows = []

    def scene_with(tag, overrides=None):
        return write_scene(base, os.path.join(args.out, f"scene_{tag}.json"), args.scale, overrides)

    base_scene = scene_with("base")
    ref = os.path.join(args.out, f"reference_{args.ref_spp}spp_scale{args.scale}.exr")
    if not os.path.exists(ref):
        log(f"converged reference: {args.ref_spp} spp, step {step / 4}")
        # The plain march (no light roulette): an estimator independent of
        # the default's.
        ref_scene = scene_with("reference", {"step_cells": step / 4, "light_roulette": 0.0})
        secs, _ = r.timed([args.exe, "render", ref_scene, "-o", ref, "--spp", str(args.ref_spp),
                           "--quiet"])
        log(f"reference took {secs:.1f} s")

    def point(series, label, cmd_of, runs=args.runs, extra_seconds=0.0, setting=""):
        image = os.path.join(args.out, f"{series}_{label}.exr".replace(" ", "_").replace("/", "-"))
        times = []
        for i in range(runs):
            secs, _ = r.timed(cmd_of(image))
            times.append(secs)
        err, psnr = r.compare(ref, image)
        row = {"scene": args.name, "series": series, "label": label, "setting": setting,
               "seconds": statistics.median(times), "runs": runs,
               "seconds_all": " ".join(f"{t:.3f}" for t in times),
               "seconds_with_bake": statistics.median(times) + extra_seconds,
               "relative_rmse": err, "psnr": psnr}
        rows.append(row)
        log(f"{series:28s} {label:22s} {row['seconds']:8.2f} s  rel. RMSE {err:.4f}  "
            f"PSNR {psnr:.2f} dB")
        return image

    def render_cmd(scene, spp_value=None):
        return lambda image: [args.exe, "render", scene, "-o", image, "--quiet"] + \
            (["--spp", str(spp_value)] if spp_value else [])

    # Every method is a curve over samples per pixel: at few samples the
    # pixel-sampling noise of a weave a few pixels per repeat dominates every
    # method alike; the curve's floor at many samples is the method's own
    # error (march step, fibre model, transmittance, bake resolution).
    spps = [1, 4, 16, 64] if not args.quick else [1, 4]

    def runs_for(n):
        return args.runs if n <= 4 else 1   # long points: one run

    def render_series(name, overrides, levels=spps):
        scene = scene_with(name.replace(" ", "_").replace(":", ""), overrides)
        for n in levels:
            point(name, f"{n} spp", render_cmd(scene, n), runs=runs_for(n),
                  setting=",".join(f"{k}={v}" for k, v in overrides.items()) + f",spp={n}")

    render_series(f"render (step {step}, scene's settings)", {})
    render_series("render: no light roulette", {"light_roulette": 0.0})
    render_series("render: step 2", {"step_cells": 2.0})
    render_series("render: step 0.125", {"step_cells": 0.125}, spps[:3])
    if not isotropic:
        render_series("render: cached transmittance", {"transmittance": "cached"})
        render_series("render: ellipsoid fibre, 16 samples", {"fiber_model": "ellipsoid",
                                                              "fiber_samples": 16}, spps[1:3])
        render_series("render: ellipsoid fibre, 64 samples", {"fiber_model": "ellipsoid",
                                                              "fiber_samples": 64}, spps[1:3])
        render_series("render: Kajiya-Kay fibre", {"fiber_model": "kajiya-kay"}, spps[1:3])

    # Bakes, then clothbake's lookup-render and Cycles reading them. A bake
    # folder from an earlier sweep of the same binary (by content), scene and
    # flags is reused (its seconds were recorded with it).
    with open(args.exe, "rb") as f:
        exe_sha256 = hashlib.sha256(f.read()).hexdigest()
    with open(base_scene, "rb") as f:
        scene_sha256 = hashlib.sha256(f.read()).hexdigest()
    bakes = [("adaptive K8", ["--adaptive", "--directions", "8", "--spp", "2"]),
             ("adaptive K16", ["--adaptive", "--directions", "16", "--spp", "2"]),
             ("adaptive K16 3tpp", ["--adaptive", "--directions", "16", "--spp", "2",
                                    "--texels-per-pixel", "3"]),
             ("full K4 R16", ["--directions", "4", "--texels", "16", "--spp", "1"]),
             ("full K8 R32", ["--directions", "8", "--texels", "32", "--spp", "1"])]
    # Cloth materials (`clothbake material`, docs/formats/material.md): baked
    # once for any camera and light; their seconds are amortised the same way.
    materials = [("material K16 KL10 (default)", []),
                 ("material K8 KL10", ["--directions", "8"]),
                 ("material K16 KL8", ["--light-directions", "8"]),
                 ("material K16 KL10 E0.02", ["--max-error", "0.02"]),
                 ("material K16 KL10 E0.2", ["--max-error", "0.2"])]
    bakes = [("bake", label, flags) for label, flags in bakes] + \
        [("material", label, flags) for label, flags in materials]
    if args.quick:
        bakes = [bakes[0], bakes[len(bakes) - len(materials)]]
    best_bake = None
    for command, label, flags in bakes:
        slug = label.replace(" ", "_").replace("(", "").replace(")", "")
        folder = os.path.join(args.out, "bake_" + slug)
        stats_path = os.path.join(args.out, "bake_" + slug + ".json")
        stats = json.load(open(stats_path)) if os.path.exists(stats_path) and \
            os.path.exists(os.path.join(folder, "manifest.json")) else None
        if stats is None or stats.get("flags") != flags or \
                stats.get("exe_sha256") != exe_sha256 or stats.get("scene_sha256") != scene_sha256:
            log(f"bake {label}")
            secs, out = r.timed([args.exe, command, base_scene, "-o", folder, "--quiet"] + flags)
            stats = dict(json.loads(out), wall_seconds=secs, flags=flags, exe_sha256=exe_sha256,
                          scene_sha256=scene_sha256)
            with open(stats_path, "w") as f:
                json.dump(stats, f, indent=2)
        bake_seconds = stats["wall_seconds"]
        series = f"lookup-render, {label}" + (" bake" if command == "bake" else "")
        for n in spps[1:]:
            point(series, f"{n} spp",
                  lambda image, n=n: [args.exe, "lookup-render", base_scene, folder, "-o", image,
                                      "--quiet", "--spp", str(n)],
                  runs=runs_for(n), extra_seconds=bake_seconds, setting=" ".join(flags))
            rows[-1]["bake_seconds"] = bake_seconds
            rows[-1]["bake_bytes_on_disk"] = stats.get("bytes_on_disk", "") or sum(
                os.path.getsize(os.path.join(folder, f)) for f in os.listdir(folder))
        if label == "adaptive K16 3tpp" or best_bake is None:
            best_bake = (label, folder, bake_seconds)

    if args.blender:
        label, folder, bake_seconds = best_bake
        with tempfile.TemporaryDirectory() as user:
            env = dict(os.environ, BLENDER_USER_SCRIPTS=user, BLENDER_USER_CONFIG=user + "/config")
            for n in ([4, 16, 64] if not args.quick else [4]):
                def cmd(image, n=n):
                    return [args.blender, "-b", "--factory-startup", "--python-exit-code", "1",
                            "-P", os.path.join(ROOT, "blender_addon", "headless_render.py"),
                            "--", base_scene, folder, image, "--samples", str(n)]
                image = os.path.join(args.out, f"cycles_bake_{n}.exr")
                times = []
                for _ in range(2 if n <= 16 else 1):
                    start = time.perf_counter()
                    proc = subprocess.run(cmd(image), stdout=subprocess.PIPE,
                                          stderr=subprocess.STDOUT, text=True, env=env)
                    times.append(time.perf_counter() - start)
                    if proc.returncode != 0:
                        raise RuntimeError(proc.stdout[-2000:])
                err, psnr = r.compare(ref, image)
                rows.append({"scene": args.name, "series": f"Cycles + {label} bake (add-on)",
                             "label": f"{n} samples", "setting": f"samples={n}",
                             "seconds": statistics.median(times), "runs": len(times),
                             "seconds_all": " ".join(f"{t:.3f}" for t in times),
                             "seconds_with_bake": statistics.median(times) + bake_seconds,
                             "relative_rmse": err, "psnr": psnr, "bake_seconds": bake_seconds})
                log(f"Cycles + bake {n:4d} samples {rows[-1]['seconds']:8.2f} s  rel. RMSE "
                    f"{err:.4f}  PSNR {psnr:.2f} dB")

    if args.extra_points:
        # Points measured elsewhere (the Cycles real-volume route): series,
        # label, seconds, image; errors computed here against this reference.
        with open(args.extra_points) as f:
            for row in csv.DictReader(f):
                err, psnr = r.compare(ref, row["image"])
                rows.append({"scene": args.name, "series": row["series"], "label": row["label"],
                             "setting": row.get("setting", ""), "seconds": float(row["seconds"]),
                             "runs": row.get("runs", 1), "seconds_all": row["seconds"],
                             "seconds_with_bake": float(row["seconds"]),
                             "relative_rmse": err, "psnr": psnr})
                log(f"{row['series']:28s} {row['label']:22s} {float(row['seconds']):8.2f} s  "
                    f"rel. RMSE {err:.4f}  PSNR {psnr:.2f} dB")

    fields = ["scene", "series", "label", "setting", "seconds", "runs", "seconds_all",
              "seconds_with_bake", "bake_seconds", "bake_bytes_on_disk", "relative_rmse", "psnr"]
    csv_path = os.path.join(args.out, "points.csv")
    with open(csv_path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow(row)
    os.replace(csv_path + ".tmp", csv_path)
    log(f"wrote {csv_path}")


if __name__ == "__main__":
    main()
