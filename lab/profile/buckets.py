#!/usr/bin/env python3
"""Sums profile.sh's perf profiles into where the time goes, per route:
self time by function, grouped into the march's parts (the first pattern a
function's name matches wins). Prints a Markdown table per route and the
largest function of each part.
    buckets.py OUT"""
import json
import os
import re
import subprocess
import sys

# (part, patterns on "DSO SYMBOL" as perf prints them), first match wins.
PARTS = [
    ("kernel: page faults, mapping memory", [r"\[kernel", r"^\S+ \[k\]"]),
    ("the material's table: read, copied, allocated (OpenEXR, zlib)",
     [r"^libz", r"libOpenEXR", r"libIex", r"libImath", r"libOpenImageIO", r"libdeflate",
      r"read_typed", r"read_material", r"ClothMaterial::allocate", r"copyIntoFrameBuffer"]),
    ("start-up and allocator", [r"^ld-linux", r"_dl_", r"do_lookup", r"malloc", r"_int_",
                                r"mem(set|cpy|move)", r"cfree"]),
    # The renderer's shadows march per sample; the bake's fields march once
    # per field point (TransmittanceCache::build's body), the node march
    # reads them (perf's callers: lab/profile/README.md).
    ("shadow DDA toward a light (render: per sample; material: the fields' build)",
     [r"optical_depth", r"shadow_transmittance"]),
    ("light fields: the rest of their build",
     [r"TransmittanceCache::build", r"LightFieldSet::build", r"layer_march"]),
    ("light fields: read at each sample",
     [r"depths_interpolated", r"LightFieldSet::transmittances", r"march_then_lookup",
      r"lookup_depth"]),
    ("fibre response: table lookup or ellipsoid",
     [r"Fiber", r"angles_of", r"grid_cell", r"normalize_safe", r"ellipsoid", r"fast_acos",
      r"__powf"]),
    ("exp (opacity, transmittance)", [r"__expf"]),
    ("view march: cell DDA, samples, compositing",
     [r"march_view", r"walk_cells", r"march_samples", r"sample_march"]),
    ("factorisation (Eigen)", [r"Eigen::"]),
    ("lookup: the material's table read and filtered",
     [r"ClothMaterial::shade", r"repeat_taps", r"ClothMaterial::"]),
    ("geometry: quads, camera", [r"QuadPatch", r"Camera", r"shade_surface"]),
    ("volume generation", [r"generate_volume"]),
]


def flat(data):
    """[(percent, "DSO SYMBOL")] of perf's self time."""
    text = subprocess.run(["perf", "report", "-q", "-i", data, "--no-children", "--sort",
                           "dso,symbol", "-g", "none", "--percent-limit", "0.05"],
                          capture_output=True, text=True, check=True).stdout
    rows = []
    for line in text.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+(\S+)\s+(\[.\])\s+(.*)", line)
        if m:
            rows.append((float(m.group(1)), f"{m.group(2)} {m.group(3)} {m.group(4).strip()}"))
    return rows


def part_of(row):
    for part, patterns in PARTS:
        if any(re.search(p, row) for p in patterns):
            return part
    return "other"


def main():
    out = sys.argv[1]
    for route, title in (("render", "Reference renderer (paper scene, 16 spp, 1 thread)"),
                         ("material", "Material bake (paper cloth, defaults, 2 threads)"),
                         ("lookup", "lookup-render (paper scene from its material, 4 spp)")):
        data = os.path.join(out, route + ".data")
        if not os.path.exists(data):
            continue
        sums = {}
        top = {}
        for pct, sym in flat(data):
            part = part_of(sym)
            sums[part] = sums.get(part, 0.0) + pct
            if pct > top.get(part, (0.0, ""))[0]:
                top[part] = (pct, sym)
        per_sample = None
        if route == "render":  # --stats: march samples and the render's seconds, one thread
            log = open(os.path.join(out, "render.log")).read()
            stats = json.loads(log[log.index("{"):log.rindex("}") + 1])
            per_sample = stats["render_seconds"] / stats["march_samples"] * 1e9
            title += (f": {stats['march_samples'] / stats['render_seconds'] / 1e6:.2f} M march "
                      f"samples a second, {per_sample:.0f} ns a sample")
        print(f"\n{title}\n\n| part | share of samples | largest function |\n|---|---|---|")
        for part, pct in sorted(sums.items(), key=lambda kv: -kv[1]):
            if pct < 0.5:
                continue
            name = top[part][1].split("] ", 1)[1].replace("(anonymous namespace)::", "")
            name = re.sub(r"\(.*", "", name.replace("clothbake::", ""))[:50].strip()
            ns = f" ({pct / 100 * per_sample:.0f} ns a sample)" if per_sample else ""
            print(f"| {part} | {pct:.1f} %{ns} | `{name}` ({top[part][0]:.1f} %) |")


main()
