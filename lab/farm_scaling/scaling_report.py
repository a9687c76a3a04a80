#!/usr/bin/env python3
"""The farm's scaling figure from lab/farm_scaling/scaling.sh's measurements.

    scaling_report.py RUNS.tsv --single-seconds S --cores C --options "..." --json OUT.json --png OUT.png

RUNS.tsv: one row per submission (shards, wall_seconds, shard_seconds as a
comma list, merge_seconds), all on one machine whose tasks ran one after
another with every core each. From them:
  - on this machine: the wall time of the whole submission, and what of it is
    neither a shard nor the merge (Slurm's scheduling passes, the merge's
    dependency start): the overhead;
  - on N nodes like this one (one shard each, the parts on a shared file
    system): the slowest shard + the merge + the fixed latency of a
    submission (the overhead measured with one shard). Beyond the measured
    counts the slowest shard follows a fit t(N) = a + b / N (a: what every
    shard does whatever its share, b: the divisible work), drawn dashed.
"""
import argparse
import json
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_runs(path):
    runs = []
    with open(path) as f:
        header = f.readline().rstrip("\n").split("\t")
        for line in f:
            row = dict(zip(header, line.rstrip("\n").split("\t")))
            runs.append({"shards": int(row["shards"]),
                         "wall_seconds": float(row["wall_seconds"]),
                         "shard_seconds": [float(x) for x in row["shard_seconds"].split(",")],
                         "merge_seconds": float(row["merge_seconds"])})
    if not runs:
        sys.exit(f"{path}: no runs")
    return sorted(runs, key=lambda r: r["shards"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs")
    ap.add_argument("--single-seconds", type=float, required=True)
    ap.add_argument("--cores", type=int, required=True)
    ap.add_argument("--options", default="")
    ap.add_argument("--json", required=True)
    ap.add_argument("--png", required=True)
    a = ap.parse_args()
    runs = read_runs(a.runs)
    for r in runs:
        s = r["shard_seconds"]
        r["sum_shard_seconds"] = sum(s)
        r["max_shard_seconds"] = max(s)
        r["imbalance"] = max(s) / (sum(s) / len(s))
        r["overhead_seconds"] = r["wall_seconds"] - sum(s) - r["merge_seconds"]
    one = next((r for r in runs if r["shards"] == 1), runs[0])
    latency = max(0.0, one["overhead_seconds"])
    n = np.array([r["shards"] for r in runs], float)
    slowest = np.array([r["max_shard_seconds"] for r in runs])
    # The merge reads every part whole (a part has the whole layout), so its
    # cost grows with N: m(N) = c + d N by least squares over the runs that
    # have one (a single shard bakes straight into the output).
    mr = [r for r in runs if r["shards"] > 1]
    if len(mr) >= 2:
        (mc, md), *_ = np.linalg.lstsq(np.stack([np.ones(len(mr)), [r["shards"] for r in mr]], 1),
                                       np.array([r["merge_seconds"] for r in mr]), rcond=None)
    else:
        mc, md = (mr[0]["merge_seconds"] if mr else 0.0), 0.0
    merge_at = lambda k: float(mc + md * k)  # noqa: E731
    # t(N) = a + b / N by least squares (numpy's lstsq).
    (fix, div), *_ = np.linalg.lstsq(np.stack([np.ones_like(n), 1 / n], 1), slowest, rcond=None)
    for r in runs:
        r["projected_wall_seconds_on_n_nodes"] = r["max_shard_seconds"] + r["merge_seconds"] + latency
    far = [16, 32, 64, 128]
    projection = [{"nodes": k, "merge_seconds": merge_at(k),
                   "projected_wall_seconds": float(fix + div / k + merge_at(k) + latency)} for k in far]
    report = {"machine": {"cores": a.cores}, "material_options": a.options,
              "single_seconds": a.single_seconds, "submission_latency_seconds": latency,
              "merge_fit": {"fixed_seconds": float(mc), "per_part_seconds": float(md)},
              "slowest_shard_fit": {"fixed_seconds": float(fix), "divisible_seconds": float(div)},
              "runs": runs, "extrapolated": projection}
    tmp = a.json + ".tmp"
    with open(tmp, "w") as f:
        json.dump(report, f, indent=2)
    os.replace(tmp, a.json)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [3, 2]})
    ax.plot(n, [r["wall_seconds"] for r in runs], "o-", color="C0",
            label=f"measured: wall time on this machine ({a.cores} cores, one task at a time)")
    ax.plot(n, [r["projected_wall_seconds_on_n_nodes"] for r in runs], "s-", color="C1",
            label="projected on N nodes: slowest shard + merge + latency")
    kk = np.geomspace(n.min(), far[-1], 64)
    ax.plot(kk, fix + div / kk + mc + md * kk + latency, "--", color="C1", alpha=0.6,
            label=f"fit: slowest shard {fix:.1f} s + {div:.1f} s / N, merge {mc:.1f} s + {md:.2f} s N, latency {latency:.1f} s")
    ax.plot(kk, a.single_seconds / kk, ":", color="grey", label="ideal: single bake / N")
    ax.axhline(a.single_seconds, color="k", lw=0.8, label=f"single bake, no farm: {a.single_seconds:.1f} s")
    ax.plot(n[n > 1], [r["merge_seconds"] for r in runs if r["shards"] > 1], "^-", color="C2",
            label="measured: the merge")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("shards (= nodes, for the projection)")
    ax.set_ylabel("seconds")
    ax.set_title(f"clothbake material {a.options}: wall time against shards")
    ax.legend(fontsize=7.5, loc="lower left")
    ax.grid(True, which="both", alpha=0.3)
    for r in runs:
        s = r["shard_seconds"]
        bx.scatter([r["shards"]] * len(s), s, s=14, color="C0")
        bx.plot([r["shards"] * 0.9, r["shards"] * 1.1], [np.mean(s)] * 2, color="k", lw=1)
        bx.annotate(f"max/mean {r['imbalance']:.2f}", (r["shards"], max(s)),
                    textcoords="offset points", xytext=(4, 4), fontsize=7)
    bx.set_xscale("log", base=2)
    bx.set_yscale("log")
    bx.set_xlabel("shards")
    bx.set_ylabel("seconds per shard (bar: mean)")
    bx.set_title("each shard's time: the balance of the split")
    bx.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    tmp = a.png + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, a.png)
    for r in runs:
        print(f"{r['shards']:3d} shards: wall {r['wall_seconds']:7.2f} s, shards sum {r['sum_shard_seconds']:7.2f} s "
              f"max {r['max_shard_seconds']:6.2f} s (max/mean {r['imbalance']:.2f}), merge {r['merge_seconds']:.2f} s, "
              f"overhead {r['overhead_seconds']:.2f} s; on {r['shards']} nodes {r['projected_wall_seconds_on_n_nodes']:.2f} s")
    for p in projection:
        print(f"extrapolated, {p['nodes']} nodes: {p['projected_wall_seconds']:.2f} s (merge {p['merge_seconds']:.2f} s)")


if __name__ == "__main__":
    main()
