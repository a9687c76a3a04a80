"""Draws the speed-against-accuracy chart from lab/chart/chart.py's CSV:
relative RMSE against seconds on log axes, one series per method, the
Pareto front (no other point both faster and more accurate) marked. For
bake-based points a hollow marker joined by a dotted line shows the same
image's cost with the bake's own seconds added.

    /usr/bin/python3 lab/chart/plot_chart.py POINTS.csv OUT_STEM [--title T]
writes OUT_STEM.png and OUT_STEM.svg, and OUT_STEM.md: the same points as a
Markdown table (docs/design/results.md quotes it), Pareto points in bold.
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = "osD^v<>pP*Xh"


def pareto(points):
    """Indices of the points no other point beats on both axes."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def write_table(rows, front, path, machine):
    """The points as a Markdown table in the CSV's order; Pareto points bold."""
    lines = ["| method | setting | seconds | seconds with bake | rel. RMSE | PSNR (dB) |",
             "|---|---|---:|---:|---:|---:|"]
    for i, r in enumerate(rows):
        secs, with_bake = float(r["seconds"]), float(r["seconds_with_bake"] or r["seconds"])
        cells = [r["series"], r["label"], f"{secs:.2f}",
                 f"{with_bake:.1f}" if with_bake > secs * 1.01 else "",
                 f"{float(r['relative_rmse']):.4f}", f"{float(r['psnr']):.2f}"]
        if i in front:
            cells = [f"**{c}**" if c else c for c in cells]
        lines.append("| " + " | ".join(cells) + " |")
    if machine and os.path.exists(machine):
        with open(machine) as f:
            lines += ["", "Machine and build:", "", "```", f.read().rstrip(), "```"]
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("out_stem")
    ap.add_argument("--title", default="")
    ap.add_argument("--machine", help="a text file describing the machine, quoted under the table")
    args = ap.parse_args()
    with open(args.csv) as f:
        rows = list(csv.DictReader(f))
    series = []
    for row in rows:
        if row["series"] not in series:
            series.append(row["series"])

    fig, ax = plt.subplots(figsize=(10, 6.5), dpi=110)
    # tab20's dark shades for the first ten series, its light ones after, so
    # no two series share a colour.
    cmap = plt.get_cmap("tab20")
    for k, name in enumerate(series):
        pts = [r for r in rows if r["series"] == name]
        xs = [float(r["seconds"]) for r in pts]
        ys = [float(r["relative_rmse"]) for r in pts]
        color = cmap((2 * k) % 20 if k < 10 else (2 * (k - 10) + 1) % 20)
        ax.plot(xs, ys, MARKERS[k % len(MARKERS)], color=color, label=name, markersize=7,
                linestyle="-" if len(pts) > 1 else "none", linewidth=0.8)
        for r, x, y in zip(pts, xs, ys):
            ax.annotate(r["label"], (x, y), textcoords="offset points", xytext=(5, 3),
                        fontsize=7, color=color)
            with_bake = float(r["seconds_with_bake"] or r["seconds"])
            if with_bake > x * 1.01:
                ax.plot([x, with_bake], [y, y], ":", color=color, linewidth=0.8)
                ax.plot([with_bake], [y], MARKERS[k % len(MARKERS)], color=color,
                        markerfacecolor="none", markersize=7)
    pts = [(float(r["seconds"]), float(r["relative_rmse"])) for r in rows]
    front = pareto(pts)
    fx = [pts[i][0] for i in front]
    fy = [pts[i][1] for i in front]
    ax.step(fx, fy, where="post", color="black", linewidth=1.2, alpha=0.6,
            label="Pareto front (bake reused)")
    ax.plot(fx, fy, "o", markersize=13, markerfacecolor="none", markeredgecolor="black",
            alpha=0.6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds per image (wall, median; hollow: + the bake's seconds)")
    ax.set_ylabel("relative RMSE against the converged reference")
    ax.grid(True, which="both", alpha=0.25)
    ax.set_title(args.title)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out_stem)), exist_ok=True)
    for ext in ("png", "svg"):
        # No date in the SVG's metadata: the same points give the same bytes.
        fig.savefig(f"{args.out_stem}.{ext}.tmp", format=ext,
                    metadata={"Date": None} if ext == "svg" else None)
        os.replace(f"{args.out_stem}.{ext}.tmp", f"{args.out_stem}.{ext}")
    write_table(rows, set(front), f"{args.out_stem}.md", args.machine)
    print(f"wrote {args.out_stem}.png/.svg/.md; Pareto front: " +
          ", ".join(f"{rows[i]['series']} {rows[i]['label']}" for i in front))


if __name__ == "__main__":
    main()
