#!/usr/bin/env python3
"""The results table of bench/README.md, from Google Benchmark JSON.

    build/bench/ssgi_bench --benchmark_filter=... --benchmark_repetitions=5 \\
        --benchmark_report_aggregates_only=true \\
        --benchmark_out_format=json --benchmark_out=bench/results/latest.json
    python3 bench/results_table.py bench/results/latest.json --command "the command above"

Reads one or more `--benchmark_out_format=json` files and prints Markdown: a line naming the
machine (the JSON's context: host_name, num_cpus, mhz_per_cpu, caches), the date (context.date)
and the command, then one row per benchmark run: its median real time (the `_median` aggregate, or
the median of the repetitions when the file holds them alone), the repetitions' coefficient of
variation (a cv of more than a few percent says the machine was busy), items per second and its
counters, named as the benchmark reports them. Then the ratios the targets are quoted as, for the pairs the
files hold: ssgi against the llvmpipe peer, and streaming passes against their memory floors, each
pair from the same run. Python 3 standard library only.
"""
import argparse
import json
import re
import statistics
import sys

# Keys of a benchmark entry that are not user counters.
STANDARD_KEYS = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
    "repetition_index", "threads", "aggregate_name", "aggregate_unit", "iterations", "real_time",
    "cpu_time", "time_unit", "items_per_second", "bytes_per_second", "label", "error_occurred",
    "error_message", "cv",
}
TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}

# (numerator run name, denominator run name with the numerator's groups, what the ratio says).
# Ratios are numerator time / denominator time.
RATIOS = [
    (r"BM_GBufferLlvmpipe/(?P<args>.*)", "BM_GBufferSsgi/{args}", "ssgi's G-buffer pass speed / llvmpipe's"),
    (r"BM_FillrateLlvmpipe/(?P<args>.*)", "BM_FillrateRasterize/{args}", "ssgi's fill rate / llvmpipe's"),
    (r"BM_HiZ/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:4/write:5/size:{size}/threads:{threads}/real_time", "Hi-Z time / its memory floor"),
    (r"BM_ColorPyramid/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:12/write:16/size:{size}/threads:{threads}/real_time",
     "colour pyramid time / its memory floor"),
    (r"BM_Composite/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:16/write:24/size:{size}/threads:{threads}/real_time", "composite time / its memory floor"),
    (r"BM_Tonemap/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:12/write:3/size:{size}/threads:{threads}/real_time", "tonemap time / its memory floor"),
    (r"BM_SkyLight/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:24/write:40/size:{size}/threads:{threads}/real_time", "sky light time / its memory floor"),
    (r"BM_CompositeEveryTerm/simd:1/size:(?P<size>\d+)/threads:(?P<threads>\d+)/real_time",
     "BM_MemoryFloor/read:84/write:24/size:{size}/threads:{threads}/real_time",
     "composite with every term time / its memory floor"),
]


def significant(x, digits=3):
    """x with `digits` significant digits, without an exponent for the usual ranges."""
    if x == 0 or x != x:
        return "0" if x == 0 else "nan"
    text = "%.*g" % (digits, x)
    if "e" in text:  # %g switched to an exponent: write the digits out
        text = "%.*f" % (max(0, digits - 1 - int(f"{abs(x):e}".split("e")[1])), x)
    return text


def with_prefix(x):
    """A large rate with an SI prefix: 1.82e8 -> '182 M'."""
    for factor, prefix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(x) >= factor:
            return "%s %s" % (significant(x / factor), prefix)
    return significant(x)


def counter_text(value):
    if float(value).is_integer() and abs(value) < 1e7:
        return "{:,}".format(int(value))
    if abs(value) >= 1e4:
        return with_prefix(value)
    return significant(value)


def load(paths):
    """The files' contexts and their runs: run name -> entry with the median's values."""
    contexts, runs = [], {}
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        contexts.append(data.get("context", {}))
        medians, cvs, repetitions, order = {}, {}, {}, []
        for entry in data.get("benchmarks", []):
            run = entry.get("run_name", entry["name"])
            if run not in order:
                order.append(run)
            if entry.get("run_type") == "aggregate":
                if entry.get("aggregate_name") == "median":
                    medians[run] = entry
                elif entry.get("aggregate_name") == "cv":
                    cvs[run] = entry.get("real_time")
            else:
                repetitions.setdefault(run, []).append(entry)
        # Registration order (the files' order is shuffled by --benchmark_enable_random_interleaving).
        first = {}
        for entry in data.get("benchmarks", []):
            first.setdefault(entry.get("run_name", entry["name"]),
                             (entry.get("family_index", 0), entry.get("per_family_instance_index", 0)))
        order.sort(key=lambda run: first[run])
        for run in order:
            if run in medians:
                runs[run] = dict(medians[run], cv=cvs.get(run))
            elif run in repetitions:
                runs[run] = median_of(repetitions[run])
    return contexts, runs


def median_of(entries):
    """One entry holding the median of each number over the repetitions (errors kept as they are)."""
    failed = [e for e in entries if e.get("error_occurred")]
    if failed:
        return failed[0]
    out = dict(entries[0])
    times = [e["real_time"] for e in entries]
    out["cv"] = statistics.pstdev(times) / statistics.mean(times) if len(times) > 1 and statistics.mean(times) else None
    for key, value in entries[0].items():
        if key not in ("family_index", "per_family_instance_index", "repetitions", "repetition_index",
                       "threads") and isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = statistics.median(e.get(key, 0.0) for e in entries)
    return out


def real_ms(entry):
    return entry["real_time"] * TO_MS.get(entry.get("time_unit", "ns"), 1e-6)


def machine_line(context):
    caches = []
    for cache in context.get("caches", []):
        kind = {"Data": "d", "Instruction": "i"}.get(cache.get("type"), "")
        size = cache.get("size", 0)
        size_text = "%d MiB" % (size >> 20) if size >= 1 << 20 else "%d KiB" % (size >> 10)
        shared = " shared by %d" % cache["num_sharing"] if cache.get("num_sharing", 1) > 1 else ""
        caches.append("L%d%s %s%s" % (cache.get("level", 0), kind, size_text, shared))
    text = "host `%s`, %s CPUs at %s MHz" % (context.get("host_name", "?"), context.get("num_cpus", "?"),
                                           context.get("mhz_per_cpu", "?"))
    if caches:
        text += " (caches: %s)" % ", ".join(caches)
    if context.get("load_avg"):
        text += ", load average %s at the start" % " / ".join("%.1f" % x for x in context["load_avg"])
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("json", nargs="+", help="Google Benchmark JSON files (--benchmark_out_format=json)")
    parser.add_argument("--command", default="", help="the command that produced the files, quoted in the header")
    parser.add_argument("--counters", default="", metavar="REGEX",
                        help="show only the counters whose names match (default: every counter)")
    args = parser.parse_args()

    try:
        contexts, runs = load(args.json)
    except (OSError, ValueError, KeyError) as error:
        sys.exit("results_table.py: error: %s" % error)
    if not runs:
        sys.exit("results_table.py: error: no benchmark runs in %s" % ", ".join(args.json))

    machines = []
    for context in contexts:
        line = machine_line(context)
        if line not in machines:
            machines.append(line)
    dates = sorted({c.get("date", "?") for c in contexts})
    print("Machine: %s. Date: %s." % ("; ".join(machines), ", ".join(dates)))
    if args.command:
        print("Command: `%s`" % args.command)
    print()

    wanted = re.compile(args.counters) if args.counters else None
    print("| benchmark | median real time | cv | items/s | counters |")
    print("|---|---|---|---|---|")
    for name, entry in runs.items():
        shown = name[:-len("/real_time")] if name.endswith("/real_time") else name
        if entry.get("error_occurred"):
            print("| `%s` | skipped: %s | | | |" % (shown, entry.get("error_message", "").replace("|", "/")))
            continue
        items = entry.get("items_per_second")
        counters = []
        if entry.get("bytes_per_second"):
            counters.append("bytes_per_second %sB/s" % with_prefix(entry["bytes_per_second"]))
        for key, value in entry.items():
            if key in STANDARD_KEYS or not isinstance(value, (int, float)) or isinstance(value, bool):
                continue
            if wanted and not wanted.search(key):
                continue
            counters.append("%s %s" % (key, counter_text(value)))
        cv = "%.0f%%" % (100 * entry["cv"]) if entry.get("cv") is not None else ""
        print("| `%s` | %s ms | %s | %s | %s |" % (shown, significant(real_ms(entry)), cv,
                                                   with_prefix(items) if items else "", ", ".join(counters)))

    ratios = []
    for numerator, denominator, meaning in RATIOS:
        for name, entry in runs.items():
            match = re.fullmatch(numerator, name)
            if not match or entry.get("error_occurred"):
                continue
            other = runs.get(denominator.format(**match.groupdict()))
            if other is None or other.get("error_occurred"):
                continue
            ratios.append((meaning, name, real_ms(entry), other["name"].replace("_median", ""), real_ms(other)))
    if ratios:
        print()
        print("| ratio, same run | numerator | denominator | ratio |")
        print("|---|---|---|---|")
        for meaning, a, a_ms, b, b_ms in ratios:
            strip = lambda n: n[:-len("/real_time")] if n.endswith("/real_time") else n
            print("| %s | `%s` %s ms | `%s` %s ms | %.2fx |" % (meaning, strip(a), significant(a_ms), strip(b),
                                                               significant(b_ms), a_ms / b_ms))


if __name__ == "__main__":
    main()
