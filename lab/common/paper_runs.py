"""What the material measurement scripts share (addressed_drafts/,
opaque_cells/, seed_floor/): running clothbake with its command echoed and
timed, and the paper scene with another cloth."""
import json
import os
import subprocess
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PAPER = os.path.join(ROOT, "testscenes", "paper")


def run(cmd):
    """Runs cmd (the program's name shown without its folder); returns
    (seconds, stdout); raises with the tail of stderr when it fails."""
    print("  " + " ".join(os.path.basename(c) if i == 0 else c for i, c in enumerate(cmd)),
          flush=True)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr[-2000:])
    return time.perf_counter() - t0, p.stdout


def write_paper_scene(cloth_path, repeats_per_uv, out_path, reference):
    """The paper scene's folds, camera and lights with the cloth at
    cloth_path; reference: a quarter of the march step, no light roulette,
    seed 7 (the references of docs/design/material.md)."""
    scene = json.load(open(os.path.join(PAPER, "scene.json")))
    scene["objects"][0].update(mesh=os.path.join(PAPER, "cloth.obj"), cloth=cloth_path,
                               repeats_per_uv=repeats_per_uv)
    if reference:
        r = scene.setdefault("render", {})
        r.update(step_cells=r.get("step_cells", 0.5) / 4, light_roulette=0.0, seed=7)
    with open(out_path, "w") as f:
        json.dump(scene, f, indent=1)
    return out_path
