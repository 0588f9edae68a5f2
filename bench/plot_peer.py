#!/usr/bin/env python3
"""ssgi against Mesa llvmpipe (the G-buffer target, docs/design.md §13): the G-buffer pass and the
fill rate, from one run of ssgi_bench, as the plots of docs/user-guide.md and their tables.

    python3 bench/plot_peer.py --run build/bench/ssgi_bench docs/   # runs the benchmarks (a few minutes), then plots
    python3 bench/plot_peer.py docs/                                # plots docs/llvmpipe_peer.json again

Writes into the folder: llvmpipe_peer.json (the run: medians of 3 repetitions), gbuffer_vs_triangles.svg
and gbuffer_vs_resolution.svg (time against triangle count at 1024x1024, against the image side at
100k triangles; 2 threads), and prints the tables in Markdown. The plots are plain SVG written here,
so nothing beyond Python 3 is needed."""
import argparse
import json
import math
import os
import subprocess
import sys

BENCH_FILTER = "BM_GBuffer(Ssgi|Llvmpipe)/|BM_Fillrate(Rasterize|Llvmpipe)/"
SSGI_COLOUR, PEER_COLOUR = "#d62728", "#1f77b4"


def run_benchmarks(binary, json_path):
    # Random interleaving runs the repetitions of all benchmarks in a shuffled order, so that load from
    # other jobs on a shared machine falls on ssgi and llvmpipe alike instead of on whichever ran then.
    subprocess.run([binary, "--benchmark_filter=" + BENCH_FILTER, "--benchmark_repetitions=3",
                    "--benchmark_enable_random_interleaving=true",
                    "--benchmark_report_aggregates_only=true", "--benchmark_min_time=0.3",
                    "--benchmark_out_format=json", "--benchmark_out=" + json_path], check=True)


def load_medians(json_path):
    """{(benchmark, args): row} of the median rows; args is a dict of the named arguments."""
    with open(json_path) as f:
        run = json.load(f)
    medians = {}
    for row in run["benchmarks"]:
        if row.get("aggregate_name") != "median" or row.get("error_occurred"):
            continue
        parts = row["run_name"].split("/")
        args = dict(part.split(":") for part in parts[1:] if ":" in part)
        medians[(parts[0], tuple(sorted((k, int(v)) for k, v in args.items())))] = row
    return run["context"], medians


def ms(row):
    scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[row["time_unit"]]
    return row["real_time"] * scale


def find(medians, name, **args):
    return medians.get((name, tuple(sorted(args.items()))))


def gbuffer_table(medians):
    lines = ["| triangles | threads | llvmpipe ms | ssgi ms | ssgi speed / llvmpipe's | covered (ssgi / llvmpipe) |",
             "|---|---|---|---|---|---|"]
    for scene in (10000, 100000, 1000000):
        for threads in (1, 2):
            ours = find(medians, "BM_GBufferSsgi", scene=scene, threads=threads, size=1024)
            peer = find(medians, "BM_GBufferLlvmpipe", scene=scene, threads=threads, size=1024)
            if ours is None or peer is None:
                continue
            lines.append("| %s | %d | %.1f | %.1f | %.2fx | %.1f%% / %.1f%% |" % (
                "{:,}".format(scene), threads, ms(peer), ms(ours), ms(peer) / ms(ours),
                100 * ours["covered"], 100 * peer["covered"]))
    return "\n".join(lines)


def fillrate_table(medians):
    lines = ["| area (px) | triangles | threads | llvmpipe ms | ssgi ms | ssgi speed / llvmpipe's | llvmpipe Mtris/s | ssgi Mtris/s | llvmpipe Mpixels/s | ssgi Mpixels/s |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for area in (10, 50, 100, 250, 500):
        for threads in (1, 2):
            ours = find(medians, "BM_FillrateRasterize", area=area, threads=threads)
            peer = find(medians, "BM_FillrateLlvmpipe", area=area, threads=threads)
            if ours is None or peer is None:
                continue
            lines.append("| %d | %s | %d | %.1f | %.1f | %.2fx | %.2f | %.2f | %.0f | %.0f |" % (
                area, "{:,}".format(int(ours["triangles"])), threads, ms(peer), ms(ours), ms(peer) / ms(ours),
                peer["items_per_second"] / 1e6, ours["items_per_second"] / 1e6,
                peer["pixels"] / 1e6, ours["pixels"] / 1e6))
    return "\n".join(lines)


def log_ticks(low, high):
    """1-2-5 ticks covering [low, high]."""
    ticks = []
    decade = 10.0 ** math.floor(math.log10(low))
    while decade <= high * 10:
        ticks += [m * decade for m in (1, 2, 5) if low <= m * decade <= high]
        decade *= 10
    return ticks


def number(value):
    return "{:,}".format(int(value)) if value >= 1 else "%g" % value


def svg_plot(path, title, note, x_label, series, x_ticks, x_tick_labels):
    """A log-log line plot: series is [(label, colour, [(x, y), ...])]."""
    width, height = 640, 420
    left, right, top, bottom = 70, 20, 40, 60
    xs = [x for _, _, points in series for x, _ in points]
    ys = [y for _, _, points in series for _, y in points]
    x_low, x_high = min(xs) / 1.25, max(xs) * 1.25
    y_low, y_high = min(ys) / 1.5, max(ys) * 1.5
    px = lambda x: left + (math.log(x) - math.log(x_low)) / (math.log(x_high) - math.log(x_low)) * (width - left - right)
    py = lambda y: height - bottom - (math.log(y) - math.log(y_low)) / (math.log(y_high) - math.log(y_low)) * (height - top - bottom)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="sans-serif" font-size="12">' % (width, height, width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="20" text-anchor="middle" font-size="14">%s</text>' % (width // 2, title),
           '<text x="%d" y="34" text-anchor="middle" font-size="10" fill="#555">%s</text>' % (width // 2, note)]
    for y in log_ticks(y_low, y_high):
        out.append('<line x1="%d" x2="%d" y1="%.1f" y2="%.1f" stroke="#ddd"/>' % (left, width - right, py(y), py(y)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (left - 6, py(y) + 4, number(y)))
    for x, label in zip(x_ticks, x_tick_labels):
        out.append('<line x1="%.1f" x2="%.1f" y1="%d" y2="%d" stroke="#ddd"/>' % (px(x), px(x), top, height - bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%s</text>' % (px(x), height - bottom + 16, label))
    out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#333"/>' % (
        left, top, width - left - right, height - top - bottom))
    out.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % ((left + width - right) // 2, height - 18, x_label))
    out.append('<text transform="translate(18 %d) rotate(-90)" text-anchor="middle">milliseconds per frame (median, log scale)</text>'
               % ((top + height - bottom) // 2))
    for index, (label, colour, points) in enumerate(series):
        coordinates = " ".join("%.1f,%.1f" % (px(x), py(y)) for x, y in points)
        out.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"/>' % (coordinates, colour))
        for x, y in points:
            out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (px(x), py(y), colour))
            # The first series' values above its points, the second's below, so that close points stay readable.
            out.append('<text x="%.1f" y="%.1f" font-size="10" fill="%s">%.1f</text>' % (
                px(x) + 6, py(y) + (-6 if index == 0 else 14), colour, y))
        legend_y = top + 18 + 18 * index
        out.append('<line x1="%d" x2="%d" y1="%d" y2="%d" stroke="%s" stroke-width="2"/>' % (
            left + 12, left + 36, legend_y, legend_y, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (left + 42, legend_y + 4, label))
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def plots(medians, context, folder):
    machine = "%d cores, 2 threads" % context["num_cpus"]
    # On a shared machine the load says how far to trust the absolute times (ratios suffer less).
    note = "run of %s, load average %.1f at its start" % (context["date"][:16].replace("T", " "), context["load_avg"][0])
    sweeps = [("gbuffer_vs_triangles.svg", "G-buffer at 1024x1024 (%s)" % machine, "triangles (torus knot, log scale)",
               "scene", (10000, 30000, 100000, 300000, 1000000), {"size": 1024}),
              ("gbuffer_vs_resolution.svg", "G-buffer, 100k triangles (%s)" % machine, "image side, pixels (log scale)",
               "size", (512, 1024, 2048, 4096), {"scene": 100000})]
    for file, title, x_label, swept, values, fixed in sweeps:
        series = []
        for name, label, colour in (("BM_GBufferSsgi", "ssgi (RunGBuffer: raster + resolve)", SSGI_COLOUR),
                                    ("BM_GBufferLlvmpipe", "Mesa llvmpipe 22.3 (clear + draw + glFinish)", PEER_COLOUR)):
            points = []
            for value in values:
                row = find(medians, name, threads=2, **{swept: value}, **fixed)
                if row is not None:
                    points.append((value, ms(row)))
            if points:
                series.append((label, colour, points))
        if not series:
            sys.exit("plot_peer.py: error: the run has no %s rows" % swept)
        labels = ["%dk" % (v // 1000) if v < 1000000 else "1M" for v in values] if swept == "scene" else [str(v) for v in values]
        svg_plot(os.path.join(folder, file), title, note, x_label, series, values, labels)
        print("wrote %s" % os.path.join(folder, file))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="where the run's JSON is (or goes) and the plots go")
    parser.add_argument("--run", metavar="SSGI_BENCH", help="run this ssgi_bench first (else replot the folder's JSON)")
    args = parser.parse_args()
    json_path = os.path.join(args.folder, "llvmpipe_peer.json")
    if args.run:
        run_benchmarks(args.run, json_path)
    context, medians = load_medians(json_path)
    if not any(name == "BM_GBufferLlvmpipe" for name, _ in medians):
        sys.exit("plot_peer.py: error: %s has no llvmpipe rows (was ssgi_bench built with EGL? see bench/README.md)" % json_path)
    plots(medians, context, args.folder)
    print("\nG-buffer pass, 1024x1024, torus knots (medians of 3):\n")
    print(gbuffer_table(medians))
    print("\nFill rate, 1024x1024, back-to-front random triangles (medians of 3):\n")
    print(fillrate_table(medians))


if __name__ == "__main__":
    main()
