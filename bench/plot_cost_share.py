#!/usr/bin/env python3
"""Plots frame time against the share of the image that needs reflections (BM_FrameReflectionShare)
and against the share in penumbra (BM_FramePenumbraShare, bench/plan_bench.cpp), each beside the
frame with the effect switched off (and, for penumbrae, the frame with hard shadows: the blur
switched off), from ssgi_bench's JSON output.

    build/bench/ssgi_bench --benchmark_filter='BM_Frame(Reflection|Penumbra)Share' --benchmark_repetitions=5 \\
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
    medians = [r for r in runs if r.get("aggregate_name", "median") == "median"]

    def series(name, counter, effect, keep):
        runs = [r for r in medians if r["name"].startswith(name) and "/keep:%d" % keep in r["name"]]
        on = sorted((100.0 * r[counter], r["real_time"]) for r in runs if "/%s:1/" % effect in r["name"])
        off = [r["real_time"] for r in runs if "/%s:0/" % effect in r["name"]]
        hard = [r["real_time"] for r in runs if "/%s:2/" % effect in r["name"]]
        return on, off, hard

    panels = [("BM_FrameReflectionShare", "reflectionShare", "reflections", "pixels that need reflections"),
              ("BM_FramePenumbraShare", "penumbraShare", "shadows", "tiles the shadow blur runs on")]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.0), dpi=100)
    for ax, (name, counter, effect, label) in zip(axes, panels):
        top = 0.0
        for keep, colour, how in [(1, "tab:blue", "buffers kept"), (0, "tab:orange", "freed, as ssgi render")]:
            on, off, hard = series(name, counter, effect, keep)
            if not on or not off:
                if keep == 1:
                    sys.exit("no %s medians in %s" % (name, args.json))
                continue
            ax.plot([p[0] for p in on], [p[1] for p in on], "o-", color=colour,
                    label="%s auto (frame plan), %s" % (effect, how))
            ax.axhline(off[0], color=colour, linestyle="--", alpha=0.6, label="%s off, %s" % (effect, how))
            if hard:
                ax.axhline(hard[0], color="tab:green", linestyle=":", label="blur off (hard shadows), %s" % how)
            top = max(top, max(p[1] for p in on))
        ax.set_xlabel("%s (%% of the image)" % label)
        ax.set_ylabel("frame time (ms, median)")
        ax.set_xlim(-2, 100)
        ax.set_ylim(0, top * 1.1)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right" if effect == "reflections" else "upper left", fontsize="small")
    fig.suptitle("1024x1024, 2 threads: frame time against the need for each effect")
    fig.tight_layout()
    fig.savefig(args.png)


if __name__ == "__main__":
    main()
