#!/usr/bin/env python3
"""Compare two Google Benchmark JSON outputs (stdlib only).

    bench/compare_runs.py BASELINE.json CONTENDER.json [--metric NAME ...] [--filter REGEX]

For every benchmark present in both runs it prints the median and mean of the
time and of the rate counters (by default vertices_per_second and
unique_vertices_per_second), and the ratio contender/baseline. Works on runs
written with --benchmark_report_aggregates_only=true (uses the median/mean
aggregates) and on plain runs (computes median/mean over the repetitions).

Warns (on stderr) when the two runs were measured on a different GL renderer,
GPU timing method, model, yarn, CPU count or library build type: their numbers
are then not comparable. Exit status 0; 2 on unusable input.

Google's own tools/compare.py (Debian package libbenchmark-tools,
/usr/share/benchmark/compare.py) does a U test as well but needs scipy and
numpy and compares times only.
"""
import argparse
import json
import re
import statistics
import sys

TIME_SCALE = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
CONTEXT_KEYS = ["gl_renderer", "gl_version", "gpu_timing_method", "model", "yarn", "segments", "num_cpus",
                "library_build_type", "tess_iterations"]
DEFAULT_METRICS = ["vertices_per_second", "unique_vertices_per_second"]


def load(path):
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"compare_runs: {path}: {e}")
    if "benchmarks" not in doc:
        sys.exit(f"compare_runs: {path}: no 'benchmarks' array (not a --benchmark_out_format=json file?)")
    return doc


def summarize(doc, metrics):
    """{run_name: {"time_ms": {"median": x, "mean": y}, metric: {...}}}"""
    aggregates, samples = {}, {}
    for b in doc["benchmarks"]:
        if b.get("error_occurred"):
            continue
        name = b.get("run_name", b["name"])
        values = {"time_ms": b.get("real_time", 0.0) * TIME_SCALE.get(b.get("time_unit", "ns"), 1e-9) * 1e3}
        for m in metrics:
            if m in b:
                values[m] = b[m]
        if b.get("run_type") == "aggregate":
            agg = b.get("aggregate_name")
            if agg in ("median", "mean"):
                for k, v in values.items():
                    aggregates.setdefault(name, {}).setdefault(k, {})[agg] = v
        else:
            for k, v in values.items():
                samples.setdefault(name, {}).setdefault(k, []).append(v)
    out = {}
    for name, per in samples.items():
        if name in aggregates:
            continue
        out[name] = {k: {"median": statistics.median(v), "mean": statistics.fmean(v)} for k, v in per.items()}
    out.update(aggregates)
    return out


def fmt(x):
    if x is None:
        return "-"
    a = abs(x)
    for div, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if a >= div:
            return f"{x / div:.3f}{suffix}"
    return f"{x:.3f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("baseline")
    ap.add_argument("contender")
    ap.add_argument("--metric", action="append", help="counter to compare (repeatable); default: %s" %
                    ", ".join(DEFAULT_METRICS))
    ap.add_argument("--filter", default=".*", help="regex on benchmark names")
    args = ap.parse_args()
    metrics = args.metric or DEFAULT_METRICS

    a, b = load(args.baseline), load(args.contender)
    ca, cb = a.get("context", {}), b.get("context", {})
    for k in CONTEXT_KEYS:
        if ca.get(k) != cb.get(k):
            print(f"WARNING: {k} differs: {ca.get(k)!r} vs {cb.get(k)!r}"
                  + (" -- GPU numbers are not comparable" if k in ("gl_renderer", "gpu_timing_method") else ""),
                  file=sys.stderr)
    for c, path in ((ca, args.baseline), (cb, args.contender)):
        load_avg = c.get("load_avg")
        if load_avg and c.get("num_cpus") and load_avg[0] > 0.5 * c["num_cpus"]:
            print(f"note: {path} was measured with load average {load_avg[0]:.2f} on {c['num_cpus']} CPUs",
                  file=sys.stderr)

    sa, sb = summarize(a, metrics), summarize(b, metrics)
    pattern = re.compile(args.filter)
    names = [n for n in sa if n in sb and pattern.search(n)]
    only = sorted((set(sa) ^ set(sb)))
    width = max([len(n) for n in names] + [9])
    print(f"{'benchmark':<{width}}  {'metric':<26} {'base med':>10} {'new med':>10} {'new/base':>9}"
          f" {'base mean':>10} {'new mean':>10} {'new/base':>9}")
    for n in names:
        for k in ["time_ms"] + metrics:
            if k not in sa[n] or k not in sb[n]:
                continue
            row = [f"{n:<{width}}", f"{k:<26}"]
            for stat in ("median", "mean"):
                x, y = sa[n][k].get(stat), sb[n][k].get(stat)
                ratio = y / x if x and y is not None else None
                row += [f"{fmt(x):>10}", f"{fmt(y):>10}", f"{ratio:>9.3f}" if ratio is not None else f"{'-':>9}"]
            print(" ".join(row))
    for n in only:
        if pattern.search(n):
            print(f"(only in {'baseline' if n in sa else 'contender'}: {n})", file=sys.stderr)
    for key in ("compute_over_tessellation",):
        if key in ca or key in cb:
            print(f"{key}: baseline {ca.get(key)}  contender {cb.get(key)}")


if __name__ == "__main__":
    main()
