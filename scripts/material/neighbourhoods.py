#!/usr/bin/env python3
"""How many distinct crossing neighbourhoods a draft holds (issue 24): the
size a material addressed per crossing would need, against the size of a
material that stores the whole weave repeat.

    scripts/material/neighbourhoods.py CLOTHBAKE OUT_DIR DRAFT.wif ...

For each draft the program's reading (`clothbake draft`, draft.json: the
drawdown warp_up[pick][end], the spacings and widths) is reduced to its
weave repeat (the smallest period of the drawdown and the spacings along
each axis; colours never count: a colour-free material takes them at render
time), then every crossing's neighbourhood is taken as a window of the
periodic drawdown around it, with the spacings and widths of the threads in
the window, and the distinct windows are counted:
  plus 1   the crossing, the two crossings either side along its warp end
           and along its weft pick (what a yarn's path through the crossing
           depends on: a thread's path between crossings depends only on the
           crossings on either side);
  r x r    the square window of radius r = 1, 2, 3 crossings (what a view
           ray or a shadow ray crossing r threads sees).
Writes OUT_DIR/neighbourhoods.json and prints a table; the sizes are in
texels at T texels per thread side (default 16, the paper material's 32
texels over its 2 x 2 repeat), and in MB scaled from the paper material
(104.4 MB for 32 x 32 texels, docs/material.md).
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

PAPER_MB_PER_TEXEL = 104.4 / (32 * 32)


def draft(exe, wif, out):
    folder = os.path.join(out, os.path.splitext(os.path.basename(wif))[0])
    subprocess.run([exe, "draft", wif, "-o", folder], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "draft.json")) as f:
        return json.load(f)


def smallest_period(rows):
    """The smallest p dividing len(rows) with rows[i] == rows[i % p]."""
    n = len(rows)
    for p in range(1, n + 1):
        if n % p == 0 and all(rows[i] == rows[i % p] for i in range(n)):
            return p
    return n


def weave_repeat(d):
    """(up[pick][end] as a bool array, per-end (spacing, width), per-pick
    (spacing, width)) over the weave repeat: the drawdown with each thread's
    spacing and width, colours dropped."""
    up = np.array(d["warp_up"], dtype=bool)             # picks x ends
    ends = [(tuple(up[:, e]), d["warp_spacing_mm"][e], d["warp_width_mm"][e])
            for e in range(up.shape[1])]
    picks = [(tuple(up[p, :]), d["weft_spacing_mm"][p], d["weft_width_mm"][p])
             for p in range(up.shape[0])]
    pe, pp = smallest_period(ends), smallest_period(picks)
    up = up[:pp, :pe]
    return up, [(d["warp_spacing_mm"][e], d["warp_width_mm"][e]) for e in range(pe)], \
        [(d["weft_spacing_mm"][p], d["weft_width_mm"][p]) for p in range(pp)]


def count(up, warp, weft, shape, r):
    picks, ends = up.shape
    seen = set()
    for p in range(picks):
        for e in range(ends):
            if shape == "plus":
                key = (tuple(up[(p + k) % picks, e] for k in range(-r, r + 1)),
                       tuple(up[p, (e + k) % ends] for k in range(-r, r + 1)),
                       warp[e], weft[p])
            else:
                rows = [(p + k) % picks for k in range(-r, r + 1)]
                cols = [(e + k) % ends for k in range(-r, r + 1)]
                key = (up[np.ix_(rows, cols)].tobytes(), tuple(warp[c] for c in cols),
                       tuple(weft[q] for q in rows))
            seen.add(key)
    return len(seen)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("clothbake")
    ap.add_argument("out")
    ap.add_argument("drafts", nargs="+")
    ap.add_argument("--texels-per-thread", type=int, default=16)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    t2 = a.texels_per_thread ** 2
    rows = []
    for wif in a.drafts:
        d = draft(a.clothbake, wif, a.out)
        up, warp, weft = weave_repeat(d)
        picks, ends = up.shape
        row = {"draft": os.path.basename(wif), "threads": [d["ends"], d["picks"]],
               "weave_repeat": [ends, picks], "crossings": ends * picks,
               "plus1": count(up, warp, weft, "plus", 1)}
        for r in (1, 2, 3):
            row[f"square{r}"] = count(up, warp, weft, "square", r)
        row["repeat_mb"] = ends * picks * t2 * PAPER_MB_PER_TEXEL
        rows.append(row)
        print(f"{row['draft']:24s} {d['ends']:4d} x {d['picks']:4d} threads, weave repeat "
              f"{ends:4d} x {picks:4d} ({ends * picks:6d} crossings): distinct plus-1 "
              f"{row['plus1']:5d}, 3x3 {row['square1']:5d}, 5x5 {row['square2']:5d}, 7x7 "
              f"{row['square3']:5d}; whole repeat {row['repeat_mb']:9.0f} MB, 3x3 "
              f"{row['square1'] * t2 * PAPER_MB_PER_TEXEL:7.0f} MB", flush=True)
    with open(os.path.join(a.out, "neighbourhoods.json"), "w") as f:
        json.dump({"texels_per_thread": a.texels_per_thread, "drafts": rows}, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
