#!/usr/bin/env python3
"""Draws the house of the material slice: its source files as boxes, one
row per room (cli, io, core/material_bake, core/material, core/march,
the core rooms below),
and an arrow for each #include between them. Used for docs/design/architecture.md
(before and after a restructuring: run it on two checkouts).

    scripts/dev/include_graph.py [CHECKOUT] OUT.png [--title TEXT]
"""
import argparse
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The rows, top to bottom: a file belongs to the first row whose prefix it has.
ROWS = [("cli", ["baker/cli/cmd_material", "baker/cli/cmd_lookup_render",
                 "baker/cli/material_options", "baker/cli/setting_flags"]),
        ("io", ["baker/io/material", "baker/io/lookup_io", "baker/io/data_image",
                "baker/io/folder_output", "baker/io/enum_names"]),
        ("core/material_bake", ["baker/core/material_bake/"]),
        ("core/material", ["baker/core/material/"]),
        ("core/scene", ["baker/core/scene/cloth_scene"]),
        ("core/march", ["baker/core/march/"]),
        ("core (below)", ["baker/core/fiber/fiber_shader", "baker/core/util/vector_math",
                          "baker/core/util/hex", "baker/core/bake/direction_grid",
                          "baker/core/geometry/direction_grid"])]
INCLUDE = re.compile(r'^#include "([^"]+)"', re.M)


def files(root):
    out = {}
    for base, _, names in os.walk(os.path.join(root, "baker")):
        for n in names:
            if n.endswith((".h", ".cpp")):
                path = os.path.relpath(os.path.join(base, n), root)
                out[path] = open(os.path.join(root, path), encoding="utf-8").read()
    return out


def row_of(path):
    for i, (_, prefixes) in enumerate(ROWS):
        if any(path.startswith(p) for p in prefixes):
            return i
    return None


def unit(path):
    """A .h and its .cpp are one box."""
    return os.path.splitext(path)[0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("checkout", nargs="?", default=".")
    ap.add_argument("out")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    src = files(a.checkout)
    lines = {}
    for path, text in src.items():
        if row_of(path) is not None:
            lines[unit(path)] = lines.get(unit(path), 0) + text.count("\n")
    edges = set()
    for path, text in src.items():
        if row_of(path) is None:
            continue
        for inc in INCLUDE.findall(text):
            target = unit("baker/" + inc)
            if target in lines and target != unit(path):
                edges.add((unit(path), target))
    boxes = {}
    fig, ax = plt.subplots(figsize=(16, 10))
    for r, (label, _) in enumerate(ROWS):
        members = sorted(u for u in lines if row_of(u + ".h") == r or row_of(u + ".cpp") == r)
        y = len(ROWS) - 1 - r
        ax.text(-0.6, y, label, ha="right", va="center", fontsize=11, weight="bold")
        for i, u in enumerate(members):
            x = i * (10.0 / max(len(members) - 1, 1)) if len(members) > 1 else 5.0
            boxes[u] = (x, y)
            ax.text(x, y, f"{os.path.basename(u)}\n{lines[u]} lines", ha="center", va="center",
                    fontsize=8, bbox=dict(boxstyle="round", fc="#eef3fb", ec="#4a6fa5"))
    for a_, b in edges:
        (x0, y0), (x1, y1) = boxes[a_], boxes[b]
        up = y1 > y0
        ax.annotate("", xy=(x1, y1 + 0.18 * (1 if y1 < y0 else -1)), xytext=(x0, y0),
                    arrowprops=dict(arrowstyle="->", lw=0.8, alpha=0.55,
                                    color="#c0392b" if up else "#555555",
                                    connectionstyle="arc3,rad=0.08"))
    ax.set_xlim(-2.5, 11)
    ax.set_ylim(-0.7, len(ROWS) - 0.3)
    ax.axis("off")
    total = sum(lines.values())
    ax.set_title(f"{a.title}  ({len(lines)} units, {total} lines, {len(edges)} includes; "
                 "red: an include that runs up a row)", fontsize=12)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    fig.savefig(tmp, dpi=80)
    os.replace(tmp, a.out)


if __name__ == "__main__":
    main()
