#!/usr/bin/env python3
"""Plots a sweep CSV (bench/sweep.cpp): error against frame time, one point per quality setting,
with the Pareto front (no other setting both faster and more accurate) drawn and labelled.

    python3 bench/plot_sweep.py sweep.csv sweep.png [--metric rmse_display|rmse|psnr_db|ssim|
                                                              rmse_visibility|rmse_display_indirect]

Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import argparse
import csv
import sys


def pareto_front(points, lower_is_better):
    """Indices of the points no other point beats on both time and error, sorted by time."""
    front = []
    best = None
    for i in sorted(range(len(points)), key=lambda k: (points[k][0], points[k][1] if lower_is_better else -points[k][1])):
        error = points[i][1]
        if best is None or (error < best if lower_is_better else error > best):
            front.append(i)
            best = error
    return front


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("png")
    parser.add_argument("--metric", default="rmse_display", choices=["rmse_display", "rmse", "psnr_db", "ssim", "rmse_visibility", "rmse_display_indirect"])
    parser.add_argument("--title", default="ssgi: error against time, one knob at a time")
    args = parser.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_sweep.py: error: matplotlib is missing (Debian: apt-get install python3-matplotlib)")
    with open(args.csv, newline="") as f:
        # Per-pass metrics are blank where the pass did not run (no shadows, no reflections).
        # The baseline row is the defaults, which the "high" preset row repeats.
        rows = [r for r in csv.DictReader(f) if r.get(args.metric, "") != ""]
        if any(r["knob"] == "preset" and r["value"] == "high" for r in rows):
            rows = [r for r in rows if r["knob"] != "baseline"]
    if not rows:
        sys.exit("plot_sweep.py: error: %s has no rows" % args.csv)
    lower_is_better = args.metric not in ("psnr_db", "ssim")
    points = [(float(r["frame_ms"]), float(r[args.metric])) for r in rows]
    labels = ["%s=%s" % (r["knob"], r["value"]) if r["knob"] != "baseline" else "defaults" for r in rows]
    presets = [i for i, r in enumerate(rows) if r["knob"] == "preset"]
    front = pareto_front(points, lower_is_better)
    fig, ax = plt.subplots(figsize=(8, 5.5), dpi=110)
    ax.scatter([p[0] for p in points], [p[1] for p in points], color="#999999", label="setting")
    ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "o-", color="#d62728", label="Pareto front")
    ax.scatter([points[i][0] for i in presets], [points[i][1] for i in presets], marker="s", s=60,
               facecolors="none", edgecolors="#1f77b4", label="--quality presets")
    ax.margins(x=0.1, y=0.08)
    # Labels in order of interest (presets, the front, the rest); one that would overlap a label
    # already placed is left out, so clusters of near-identical settings stay readable.
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    placed = []
    for i in presets + [i for i in front if i not in presets] + [i for i in range(len(points)) if i not in front + presets]:
        for offset, align in (((5, 4), "left"), ((5, -11), "left"), ((-5, 4), "right"), ((-5, -11), "right")):
            text = ax.annotate(labels[i].replace("preset=", ""), points[i], textcoords="offset points", xytext=offset,
                               ha=align, fontsize=8 if i in presets else 7,
                               color="#1f77b4" if i in presets else "#d62728" if i in front else "#555555")
            box = text.get_window_extent(renderer).expanded(1.05, 1.2)
            if not any(box.overlaps(other) for other in placed):
                placed.append(box)
                break
            text.remove()
    ax.set_xlabel("frame time (ms, median)")
    ax.set_ylabel({"rmse_display": "RMSE of x/(1+x) against the reference", "rmse": "RMSE against the reference (linear)",
                   "psnr_db": "PSNR (dB)", "ssim": "SSIM",
                   "rmse_visibility": "RMSE of the light visibility against the traced one",
                   "rmse_display_indirect": "RMSE of x/(1+x) of the indirect light against the traced bounce"}[args.metric])
    ax.set_title(args.title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.png)
    print("wrote %s (Pareto front: %s)" % (args.png, ", ".join(labels[i] for i in front)))


if __name__ == "__main__":
    main()
