#!/usr/bin/python3
"""The pixel-accurate shadows comparison of Luksch sec. 10, reproduced with `penumbra bench`: every configuration
(uniform sm, pssm, jittered, and whatever CONFIGS lists) on every built-in scene, five cameras each, under the
scene's light made hard (spot radius 0, sun angular radius 0), against the exact Embree reference (one ray a pixel).
Metric: the fraction of covered pixels able to receive light whose visibility is off by more than 0.1 ("wrong", the
`off` column of compare), and the median device frame time.

The five cameras come from the scene's own camera (eye E, target T) and light, so every scene gets the same cases:
  default   E -> T, the scene's view
  long      low over the ground (a tenth of E's height), looking past T to three times the distance: a long view range
  parallel  the view along the light (spot: from the light's position; sun: along its direction): duelling frusta
  facing    from the far side of T, looking back towards the light
  close     E moved 60% of the way to T: magnification, where uniform maps undersample most

usage: tools/luksch_eval.py PENUMBRA OUT_DIR [--size WxH] [--map-size N] [--runs N] [--scenes a,b] [--configs a,b]
                            [--fresh]
A case (scene, camera, config) whose CSV is already in OUT_DIR is not measured again unless --fresh.
Writes OUT_DIR/results.csv (scene, camera, config, ms, off, mae, pixels), OUT_DIR/pixel-accurate.md (the tables)
and OUT_DIR/pixel-accurate.png/svg (wrong pixels and frame time per camera, one panel row per scene; needs
Debian's python3-matplotlib)."""
import argparse
import csv
import math
import os
import subprocess
import sys

# The built-in scenes' default camera (eye, target, vertical fov) and light, as host/scene/procedural.cpp builds them
# with default parameters. Lights: ("spot", position, target, fov) or ("sun", direction). The "-sun" cases light
# the spot-lit scenes by a sun along the spot's axis, so directional-only methods (LiSPSM) are measured there too.
SCENES = {
    "box": ("box", (3, 2.5, 4), (0, 0.3, 0), 45, ("spot", (-2, 5, -1), (0, 0, 0), 60)),
    "stacked-planes": ("stacked-planes", (5, 4, 6), (0, 0.5, 0), 45, ("spot", (0.3, 6, 0.2), (0, 0, 0), 90)),
    "poles": ("poles", (1, 1.7, 4), (0, 0.8, -10), 50, ("sun", (0.6, -1, -0.3))),
    "staircase": ("staircase", (4, 4, 4.5), (0, 0.625, 0), 45, ("spot", (0.2, 6, 0.3), (0, 0, 0), 70)),
    "single-triangle": ("single-triangle", (0, 0.75, 3), (0, 0.75, 0), 45, ("spot", (0.5, 4, 2.5), (0, 0.5, 0), 60)),
    "plane": ("plane", (0, 3, 4), (0, 0, 0), 45, ("sun", (0.3, -1, 0.2))),
    "box-sun": ("box", (3, 2.5, 4), (0, 0.3, 0), 45, ("sun", (2, -5, 1))),
    "staircase-sun": ("staircase", (4, 4, 4.5), (0, 0.625, 0), 45, ("sun", (-0.2, -6, -0.3))),
}

# name -> (technique, extra bench options). The first is the baseline docs/techniques/jittered.md compares against. Configs with no
# extra options (each technique's defaults) are measured together in one `bench --interleave` call per case, so the
# ratio of their times does not carry the drift of this shared machine's speed between calls.
CONFIGS = {
    "sm": ("sm", []),
    "lispsm": ("sm", ["--warp", "lispsm"]),
    "pssm": ("pssm", ["--pssm-filter", "hard", "--pssm-splits", "auto"]),
    "pssm-lispsm": ("pssm", ["--pssm-filter", "hard", "--pssm-splits", "auto", "--warp", "lispsm"]),
    "jittered": ("jittered", []),  # its default warp is lispsm
    "jittered-uniform": ("jittered", ["--warp", "none"]),
    "jittered-lispsm-n": ("jittered", ["--lispsm-n-jitter", "1"]),
    "jittered-reduced": ("jittered", ["--warp", "none", "--jitter-reduction", "0.55"]),
    "jittered-adapted": ("jittered", ["--confidence", "adapted"]),
    "sm-id": ("sm", ["--id-buffer", "combined"]),
    "izb": ("izb", []),  # exact: the irregular z-buffer
    "fvsm": ("fvsm", []),  # fitted virtual shadow maps (its --map-size is the tile's)
    "fvsm-map": ("fvsm", ["--exact-edges", "off"]),  # fvsm decided by its tiles alone, as Giegl and Wimmer
    "jittered-map": ("jittered", ["--exact-edges", "off"]),  # jittered decided by its maps alone, as Luksch
}


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def unit(a):
    n = norm(a)
    return scale(a, 1.0 / n)


def fmt(v):
    return ",".join(f"{x:.4g}" for x in v)


def cameras(eye, target, fov, light):
    """The five cameras as `--camera` strings."""
    out = {"default": (eye, target)}
    flat = (eye[0] - target[0], 0.0, eye[2] - target[2])
    low = (target[0] + flat[0], max(0.1 * eye[1], 0.05), target[2] + flat[2])
    out["long"] = (low, (target[0] - 2 * flat[0], 0.0, target[2] - 2 * flat[2]))
    distance = norm(sub(eye, target))
    if light[0] == "spot":
        out["parallel"] = (light[1], target)
        away = unit(sub(target, light[1]))
    else:
        out["parallel"] = (sub(target, scale(unit(light[1]), distance)), target)
        away = unit(light[1])
    far = add(target, scale((away[0], 0.0, away[2]), distance))
    out["facing"] = ((far[0], eye[1], far[2]), target)
    out["close"] = (add(target, scale(sub(eye, target), 0.4)), target)
    return {k: f"{fmt(e)}:{fmt(t)}:{fov}" for k, (e, t) in out.items()}


def hard_light(light):
    if light[0] == "spot":
        return f"spot:{fmt(light[1])}:{fmt(light[2])}:{light[3]}"
    return f"dir:{fmt(light[1])}"


def run(cmd):
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode not in (0, 1):
        sys.stderr.write(result.stderr)
        raise SystemExit(f"luksch_eval.py: {' '.join(cmd)} exited {result.returncode}")
    return result


def total_row(path, technique):
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["pass"] == "total" and row["technique"] == technique and row["off"] != "":
                return row
    return None


def batches(configs):
    """The bench calls of one case: the configs without extra options together (interleaved), each other alone."""
    plain = [c for c in configs if not CONFIGS[c][1]]
    out = [plain] if plain else []
    return out + [[c] for c in configs if CONFIGS[c][1]]


def measure(args, out_dir):
    rows = []
    for scene in args.scenes:
        builtin, eye, target, fov, light = SCENES[scene]
        for cam_name, cam in cameras(eye, target, fov, light).items():
            common = [f"builtin:{builtin}", "--camera", cam, "--light", hard_light(light), "--size", args.size]
            ref = os.path.join(out_dir, f"{scene}.{cam_name}.reference.exr")
            if args.fresh or not os.path.exists(ref):
                run([args.penumbra, "reference", *common, "-o", ref, "-q"])
            for batch in batches(args.configs):
                csv_path = os.path.join(out_dir, f"{scene}.{cam_name}.{'+'.join(batch)}.csv")
                if args.fresh or not os.path.exists(csv_path):  # cases measured before are kept (delete to redo)
                    technique_list = ",".join(CONFIGS[c][0] for c in batch)
                    extra = CONFIGS[batch[0]][1] if len(batch) == 1 else ["--interleave"]
                    run([args.penumbra, "bench", *common, "--techniques", technique_list, *extra, "--map-size",
                         str(args.map_size), "--reference", ref, "--runs", str(args.runs), "--warmup", "1", "-o",
                         csv_path, "-q"])
                for config in batch:
                    row = total_row(csv_path, CONFIGS[config][0])
                    if row is None:
                        print(f"{scene} {cam_name} {config}: no result", file=sys.stderr)
                        continue
                    rows.append({"scene": scene, "camera": cam_name, "config": config, "ms": float(row["ms"]),
                                 "off": float(row["off"]), "mae": float(row["mae"]), "pixels": int(row["pixels"]),
                                 "device": row["device"]})
                    print(f"{scene:16} {cam_name:9} {config:17} {float(row['ms']):9.1f} ms  wrong "
                          f"{100 * float(row['off']):7.3f} %", file=sys.stderr)
    return rows


def write_table(rows, args, path):
    configs = [c for c in args.configs if any(r["config"] == c for r in rows)]
    base = configs[0]
    lines = [f"# Pixel-accurate shadows: the Luksch sec. 10 comparison", "",
             f"Generated by `tools/luksch_eval.py` ({args.size}, {args.map_size}² maps, median of {args.runs} runs, "
             f"device: {rows[0]['device'] if rows else '?'}). Wrong = fraction of covered pixels that can receive "
             "light with |visibility - reference| > 0.1 against the exact Embree reference under the scene's light "
             "made hard; ms = median device frame time. Cameras: see the script's docstring.", "",
             "| scene | camera | " + " | ".join(f"{c} wrong % | {c} ms" for c in configs) + " |",
             "| --- | --- | " + " | ".join("--- | ---" for _ in configs) + " |"]
    by = {(r["scene"], r["camera"], r["config"]): r for r in rows}
    keys = sorted({(r["scene"], r["camera"]) for r in rows}, key=lambda k: (args.scenes.index(k[0]), k[1]))
    for scene, cam in keys:
        cells = []
        for c in configs:
            r = by.get((scene, cam, c))
            cells.append(f"{100 * r['off']:.3f} | {r['ms']:.0f}" if r else "— | —")
        lines.append(f"| {scene} | {cam} | " + " | ".join(cells) + " |")
    lines += ["", f"Summary over every scene and camera (time relative to `{base}` on the same case):", "",
              "| config | mean wrong % | worst wrong % | cases ≤ 0.05 % | mean time × " + base + " |",
              "| --- | --- | --- | --- | --- |"]
    for c in configs:
        mine = [by[k + (c,)] for k in keys if k + (c,) in by]
        ratios = [by[k + (c,)]["ms"] / by[k + (base,)]["ms"] for k in keys if k + (c,) in by and k + (base,) in by]
        if not mine:
            continue
        mean = sum(r["off"] for r in mine) / len(mine)
        worst = max(r["off"] for r in mine)
        ok = sum(r["off"] <= 5e-4 for r in mine)
        lines.append(f"| {c} | {100 * mean:.3f} | {100 * worst:.3f} | {ok} of {len(mine)} | "
                     f"{sum(ratios) / len(ratios):.2f} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_chart(rows, args, base):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = [s for s in args.scenes if any(r["scene"] == s for r in rows)]
    configs = [c for c in args.configs if any(r["config"] == c for r in rows)]
    cams = ["default", "long", "parallel", "facing", "close"]
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from chart import pareto  # tools/chart.py, beside this script

    fig, axes = plt.subplots(len(scenes), 3, figsize=(17, 2.8 * len(scenes)), squeeze=False)
    for row_axes, scene in zip(axes, scenes):
        # Speed against accuracy, as tools/chart.py draws it: each config's mean over the five cameras, the Pareto front.
        points, names = [], []
        for c in configs:
            got = [r for r in rows if r["scene"] == scene and r["config"] == c]
            if got:
                points.append((sum(r["ms"] for r in got) / len(got),
                               max(100 * sum(r["off"] for r in got) / len(got), 1e-4)))
                names.append(c)
        front = set(pareto(points))
        for i, ((x, y), name) in enumerate(zip(points, names)):
            row_axes[2].scatter([x], [y], s=50 if i in front else 25, edgecolors="black" if i in front else "none",
                                zorder=3)
            row_axes[2].annotate(name, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
        line = sorted(front, key=lambda i: points[i][0])
        row_axes[2].plot([points[i][0] for i in line], [points[i][1] for i in line], "k--", linewidth=1)
        row_axes[2].set_xscale("log")
        row_axes[2].set_yscale("log")
        row_axes[2].set_xlabel("mean frame time, device (ms, log)", fontsize=8)
        row_axes[2].set_title(f"{scene}: mean wrong % against mean time (Pareto front dashed)", fontsize=9)
        row_axes[2].grid(True, which="both", alpha=0.3)
        for c in configs:
            got = {r["camera"]: r for r in rows if r["scene"] == scene and r["config"] == c}
            xs = [i for i, k in enumerate(cams) if k in got]
            row_axes[0].plot(xs, [max(100 * got[cams[i]]["off"], 1e-4) for i in xs], marker="o", label=c)
            row_axes[1].plot(xs, [got[cams[i]]["ms"] for i in xs], marker="o", label=c)
        for ax, title in zip(row_axes[:2], ("wrong pixels % (log)", "frame time ms (log)")):
            ax.set_yscale("log")
            ax.set_xticks(range(len(cams)), cams)
            ax.set_title(f"{scene}: {title}", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
        row_axes[0].axhline(0.05, color="black", linewidth=0.8, linestyle="--")
    axes[0][1].legend(fontsize=7)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(f"{base}.{ext}", dpi=72)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("penumbra")
    parser.add_argument("out_dir")
    parser.add_argument("--size", default="1280x720")
    parser.add_argument("--map-size", type=int, default=2048)
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--configs", default=",".join(CONFIGS))
    parser.add_argument("--fresh", action="store_true", help="measure every case again (default: reuse OUT_DIR's)")
    args = parser.parse_args()
    args.scenes = args.scenes.split(",")
    args.configs = args.configs.split(",")
    for name in args.scenes + args.configs:
        if name not in SCENES and name not in CONFIGS:
            parser.error(f"unknown scene or config '{name}'")
    os.makedirs(args.out_dir, exist_ok=True)
    rows = measure(args, args.out_dir)
    with open(os.path.join(args.out_dir, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["scene", "camera", "config", "ms", "off", "mae", "pixels", "device"])
        writer.writeheader()
        writer.writerows(rows)
    write_table(rows, args, os.path.join(args.out_dir, "pixel-accurate.md"))
    try:
        write_chart(rows, args, os.path.join(args.out_dir, "pixel-accurate"))
    except ImportError:
        print("luksch_eval.py: matplotlib is missing: no chart (Debian: python3-matplotlib)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
