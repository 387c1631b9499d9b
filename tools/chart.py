#!/usr/bin/python3
"""Speed-vs-error charts from `penumbra bench` CSV files: one chart per scene (PNG and SVG), frame time (ms, log
scale) against MAE in the left panel and against the leaking fraction in the right one, one labelled point per
technique x setting (the "total" rows), the Pareto front (no other point is both faster and more accurate) drawn
as a line through its points, which are outlined in black. A sequence CSV (`bench --camera-path ... --frames N`,
with a "shimmer" column) gets a chart of its own, SCENE-shimmer.{png,svg}: frame time against the mean MAE over the
frames and against the shimmer (mean |change of visibility| between consecutive frames where the reference is
stable), per technique x setting.

usage: tools/chart.py OUT_DIR results.csv [more.csv ...]
Needs Python 3 and matplotlib (Debian: python3-matplotlib)."""
import csv
import os
import re
import sys


def slug(scene):
    """builtin:stacked-planes -> stacked-planes, scenes/default.json -> default."""
    name = scene.split(":", 1)[1] if scene.startswith("builtin:") else os.path.splitext(os.path.basename(scene))[0]
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", name.split(":")[0]).strip("-") or "scene"


def read_totals(paths):
    """Total rows that carry metrics and sequence rows, grouped by scene and kind: {(scene, kind): [row, ...]}, kind
    "" for a single view's rows, "shimmer" for a sequence's."""
    scenes = {}
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if "shimmer" in row:  # a sequence: one row per technique x setting x light
                    for key in ("ms", "mae", "shimmer", "shimmer_fraction"):
                        row[key] = float(row[key])
                    row["runs"] = row["frames"]
                    scenes.setdefault((row["scene"], "shimmer"), []).append(row)
                    continue
                if row["pass"] != "total" or row["mae"] == "":
                    continue
                for key in ("ms", "mae", "rmse", "leak", "false_shadow"):
                    row[key] = float(row[key])
                scenes.setdefault((row["scene"], ""), []).append(row)
    return scenes


def label(row):
    return row["technique"] if row["setting"] == "default" else f'{row["technique"]} {row["setting"]}'


def pareto(points):
    """Indices of the points no other point beats on both axes (lower is better), sorted by x."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def panel(ax, rows, metric, title, colours):
    points = [(r["ms"], r[metric]) for r in rows]
    front = set(pareto(points))
    for i, (r, (x, y)) in enumerate(zip(rows, points)):
        on = i in front
        ax.scatter([x], [y], s=60 if on else 30, color=colours[r["technique"]], edgecolors="black" if on else "none",
                   linewidths=1.2, zorder=3)
        ax.annotate(label(r), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
    line = sorted(front, key=lambda i: points[i][0])
    ax.plot([points[i][0] for i in line], [points[i][1] for i in line], color="black", linewidth=1, linestyle="--",
            zorder=2, label="Pareto front")
    peer = sorted((i for i, r in enumerate(rows) if r["technique"] == "reference"), key=lambda i: points[i][0])
    if len(peer) > 1:  # the ray tracer's curve over its sample counts (bench --techniques ...,reference)
        ax.plot([points[i][0] for i in peer], [points[i][1] for i in peer], color=colours["reference"], linewidth=1.5,
                zorder=2, label="ray tracer (Embree, host wall clock)")
    ax.set_xscale("log")
    ax.set_xlabel("frame time (ms, log): device time; the ray tracer's host wall clock")
    ax.set_ylabel(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper right", fontsize=7)


def chart(scene, rows, out_dir, kind=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    techniques = sorted({r["technique"] for r in rows})
    cmap = plt.get_cmap("tab10" if len(techniques) <= 10 else "tab20")
    colours = {t: cmap(i % cmap.N) for i, t in enumerate(techniques)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    r0 = rows[0]
    if kind == "shimmer":
        panel(axes[0], rows, "mae", "mean absolute error of visibility, mean over the frames", colours)
        panel(axes[1], rows, "shimmer", "shimmer: mean |change| between frames where the reference is stable",
              colours)
        title = f'{scene}: {r0["width"]}x{r0["height"]}, {r0["frames"]} frames of a camera path, {r0["device"]}'
    else:
        panel(axes[0], rows, "mae", "mean absolute error of visibility", colours)
        panel(axes[1], rows, "leak", "leaking fraction (ref < 0.05, ours > 0.5)", colours)
        title = f'{scene}: {r0["width"]}x{r0["height"]}, median of {r0["runs"]} runs, {r0["device"]}'
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    base = os.path.join(out_dir, slug(scene) + ("-" + kind if kind else ""))
    for ext in ("png", "svg"):
        fig.savefig(f"{base}.{ext}", dpi=110)
    plt.close(fig)
    return base


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("chart.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 3
    out_dir = argv[1]
    os.makedirs(out_dir, exist_ok=True)
    scenes = read_totals(argv[2:])
    if not scenes:
        print("chart.py: no total rows with metrics in the CSV (run bench with a reference)", file=sys.stderr)
        return 1
    for (scene, kind), rows in scenes.items():
        print(f"wrote {chart(scene, rows, out_dir, kind)}.png and .svg")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
