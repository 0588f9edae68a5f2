#!/usr/bin/env python3
"""Plots frame time against the share of pixels that need reflections, from the JSON output of
BM_FrameReflectionShare (bench/plan_bench.cpp), with the frame with reflections switched off as
a reference line.

    build/bench/ssgi_bench --benchmark_filter=BM_FrameReflectionShare --benchmark_repetitions=5 \\
        --benchmark_report_aggregates_only=true --benchmark_format=json > share.json
    python3 bench/plot_cost_share.py share.json docs/images/cost_share.png

Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import argparse
import json
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json")
    parser.add_argument("png")
    args = parser.parse_args()
    with open(args.json) as f:
        runs = json.load(f)["benchmarks"]
    medians = [r for r in runs if r.get("aggregate_name", "median") == "median" and "reflectionShare" in r]
    points = sorted((100.0 * r["reflectionShare"], r["real_time"]) for r in medians if "/reflections:1/" in r["name"])
    off = [r["real_time"] for r in medians if "/reflections:0/" in r["name"]]
    if not points or not off:
        sys.exit("no BM_FrameReflectionShare medians in " + args.json)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    ax.plot([p[0] for p in points], [p[1] for p in points], "o-", label="reflections auto (frame plan)")
    ax.axhline(off[0], color="grey", linestyle="--", label="reflections off")
    ax.set_xlabel("pixels that need reflections (% of the image)")
    ax.set_ylabel("frame time (ms, median)")
    ax.set_xlim(-2, 100)
    ax.set_ylim(0, max(p[1] for p in points) * 1.1)
    ax.set_title("1024x1024, 2 threads: frame time against the need for reflections")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(args.png)


if __name__ == "__main__":
    main()
