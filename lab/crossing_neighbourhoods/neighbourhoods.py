#!/usr/bin/env python3
"""How many distinct crossing neighbourhoods a draft holds (issue 24): the
size a material addressed per crossing would need, against the size of a
material that stores the whole weave repeat.

    lab/crossing_neighbourhoods/neighbourhoods.py CLOTHBAKE OUT_DIR DRAFT.wif ...

The counts are the program's (`clothbake draft`, draft.json's
"neighbourhoods": core/weave/crossing_neighbourhoods.h): the draft over its
smallest repeat, colours not counted, each crossing's window of the periodic
drawdown with the spacing and width of every thread in it:
  plus 1   the crossing and the crossings either side along its warp end and
           its weft pick (what a yarn's path through the crossing depends on);
  r x r    the square window of radius r = 1, 2, 3 crossings (what a view
           ray or a shadow ray crossing r threads sees).
Writes OUT_DIR/neighbourhoods.json and prints a table; the sizes are in MB at
T texels per thread side (default 16, the paper material's 32 texels over its
2 x 2 repeat, and 8), scaled from the paper material (104.4 MB for 32 x 32
texels at K 16, docs/design/material.md).
"""
import argparse
import json
import os
import subprocess
import sys

PAPER_MB_PER_TEXEL = 104.4 / (32 * 32)


def draft(exe, wif, out):
    folder = os.path.join(out, os.path.splitext(os.path.basename(wif))[0])
    subprocess.run([exe, "draft", wif, "-o", folder], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "draft.json")) as f:
        return json.load(f)


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
        n = d["neighbourhoods"]
        ends, picks = n["weave_repeat"]
        row = {"draft": os.path.basename(wif), "threads": [d["ends"], d["picks"]],
               "weave_repeat": [ends, picks], "crossings": n["crossings"],
               "plus1": n["plus_1"]}
        for r in (1, 2, 3):
            row[f"square{r}"] = n[f"square_{r}"]
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
