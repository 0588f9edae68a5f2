#!/usr/bin/env python3
"""Plots a sweep CSV (bench/sweep.cpp): error against frame time, one point per quality setting,
with the Pareto front (no other setting both faster and more accurate) drawn and labelled.

    python3 bench/plot_sweep.py sweep.csv sweep.png [--metric rmse_display|rmse|psnr_db|ssim]

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
    parser.add_argument("--metric", default="rmse_display", choices=["rmse_display", "rmse", "psnr_db", "ssim"])
    args = parser.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_sweep.py: error: matplotlib is missing (Debian: apt-get install python3-matplotlib)")
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_sweep.py: error: %s has no rows" % args.csv)
    lower_is_better = args.metric in ("rmse", "rmse_display")
    points = [(float(r["frame_ms"]), float(r[args.metric])) for r in rows]
    labels = ["%s=%s" % (r["knob"], r["value"]) if r["knob"] != "baseline" else "defaults" for r in rows]
    presets = [i for i, r in enumerate(rows) if r["knob"] == "preset"]
    front = pareto_front(points, lower_is_better)
    fig, ax = plt.subplots(figsize=(8, 5), dpi=110)
    ax.scatter([p[0] for p in points], [p[1] for p in points], color="#999999", label="setting")
    ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "o-", color="#d62728", label="Pareto front")
    ax.scatter([points[i][0] for i in presets], [points[i][1] for i in presets], marker="s", s=60,
               facecolors="none", edgecolors="#1f77b4", label="--quality presets")
    for i, (t, e) in enumerate(points):
        ax.annotate(labels[i], (t, e), textcoords="offset points", xytext=(4, 3), fontsize=7,
                    color="#d62728" if i in front else "#555555")
    ax.set_xlabel("frame time (ms, median)")
    ax.set_ylabel({"rmse_display": "RMSE of x/(1+x) against the reference", "rmse": "RMSE against the reference (linear)",
                   "psnr_db": "PSNR (dB)", "ssim": "SSIM"}[args.metric])
    ax.set_title("ssgi: error against time, one knob at a time")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.png)
    print("wrote %s (Pareto front: %s)" % (args.png, ", ".join(labels[i] for i in front)))


if __name__ == "__main__":
    main()
