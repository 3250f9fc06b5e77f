#!/usr/bin/env python3
"""Derived figures of manylights-kernel-bench from its Google Benchmark JSON.

    kernel_bench_ratios.py RUN.json [--json OUT]          figures of one run
    kernel_bench_ratios.py --compare OLD.json NEW.json    two runs side by side

One run (`manylights-kernel-bench --json RUN.json`, or --benchmark_out=RUN.json
--benchmark_out_format=json): per size,
  - the fraction of the copy bound of every case: its bytes/s over the
    fastest copy's (copy.host_memcpy, copy.host_memcpy_par,
    copy.cl_enqueue_copy, copy.cl_kernel_uint4) at the same n; cases without
    copies at their n (1080p, VCT mips) use the copy size whose traffic is
    nearest to theirs;
  - the radix sort against its bandwidth bound: an LSD pass reads and writes
    every key once, i.e. one device copy of the keys (the faster of
    copy.cl_enqueue_copy and copy.cl_kernel_uint4), so
    bound(P) = n / (P x t_copy), for P = 4 (8-bit digits) and the passes the
    sorter made (its "passes" counter);
  - the speed-up of our sorts over each peer (Boost.Compute, std::sort,
    parallel std::sort) and of our tile culler over its peers (the previous
    culler with an atomic per list entry, the C++ culler on TBB): peer time /
    our time, same n, same inputs, same run.
Times are Google Benchmark's real_time (manual time): the median aggregate
when the run had --benchmark_repetitions, else the median of the runs. A case
labelled timing=host was timed by the host clock: the host peers always, and
device cases where the device's profiling clock was unusable; the latter are
marked "(host clock)". A case that reported an error (its output differed from the
C++ twin) has no figures and is listed as failed.

--compare OLD NEW: per case the two times and NEW/OLD, then the derived
figures of both runs (two commits, or two devices: PoCL against rusticl).
The standard tool reads the same files:
    /usr/share/benchmark/compare.py benchmarks OLD.json NEW.json
(Debian: libbenchmark-tools; needs python3-scipy), and within one run
    compare.py filters RUN.json radix_sort.u32 boost_compute_sort.u32
compares two cases (--standard runs the first form after our tables).

Exit status 2 with one line on a file that is not Google Benchmark JSON.
Standard library only.
"""
import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys

OUR_SORTS = ["radix_sort.u32", "bitonic_sort.u32"]
SORT_PEERS = ["boost_compute_sort.u32", "std_sort_par.u32", "std_sort.u32"]
# Ours -> its peers: every speed-up the figures list (same n, same inputs, same run).
PEERS = {ours: SORT_PEERS for ours in OUR_SORTS}
PEERS["tile_cull.minmax.1080p"] = ["tile_cull_pair_atomics.minmax.1080p", "tile_cull_cpp_tbb.minmax.1080p"]
COPIES = ["copy.host_memcpy", "copy.host_memcpy_par", "copy.cl_enqueue_copy", "copy.cl_kernel_uint4"]
DEVICE_COPIES = ["copy.cl_enqueue_copy", "copy.cl_kernel_uint4"]
HOST_CASES = {"copy.host_memcpy", "copy.host_memcpy_par", "std_sort.u32", "std_sort_par.u32",
              "tile_cull_cpp_tbb.minmax.1080p"}  # always the host clock
UNIT_SECONDS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
STANDARD_COMPARE = "/usr/share/benchmark/compare.py"


class InputError(Exception):
    pass


def load(path):
    """{(case, n): record} of a Google Benchmark JSON, and its context."""
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: cannot read Google Benchmark JSON ({e})")
    if not isinstance(doc, dict) or not isinstance(doc.get("benchmarks"), list) or "context" not in doc:
        raise InputError(f"{path}: not Google Benchmark JSON (no 'context' and 'benchmarks')")
    rows = {}
    for b in doc["benchmarks"]:
        if not isinstance(b, dict) or "name" not in b:
            raise InputError(f"{path}: a benchmark entry without a name")
        run_name = b.get("run_name", b["name"])
        parts = run_name.split("/")
        if parts and parts[-1] == "manual_time":
            parts = parts[:-1]
        if len(parts) != 2 or not parts[1].isdigit():
            continue  # not one of the kernel bench's "<case>/<n>" cases
        rows.setdefault((parts[0], int(parts[1])), []).append(b)
    return {key: summarize(path, key, entries) for key, entries in rows.items()}, doc["context"]


def summarize(path, key, entries):
    """One record per case: seconds, bytes/s, items/s, label, error, counters."""
    errors = [e.get("error_message", "error") for e in entries if e.get("error_occurred")]
    if errors:
        return {"error": errors[0]}
    medians = [e for e in entries if e.get("run_type") == "aggregate" and e.get("aggregate_name") == "median"]
    runs = [e for e in entries if e.get("run_type", "iteration") == "iteration"]
    chosen = medians or runs
    if not chosen:
        raise InputError(f"{path}: {key[0]}/{key[1]} has neither runs nor a median aggregate")
    for e in chosen:
        if e.get("time_unit") not in UNIT_SECONDS or not isinstance(e.get("real_time"), (int, float)):
            raise InputError(f"{path}: {key[0]}/{key[1]}: no real_time with a time_unit")

    def med(field, scale=1.0):
        vals = [float(e[field]) * scale for e in chosen if isinstance(e.get(field), (int, float))]
        return statistics.median(vals) if vals else None

    seconds = statistics.median([float(e["real_time"]) * UNIT_SECONDS[e["time_unit"]] for e in chosen])
    labels = {e.get("label", "") for e in entries if e.get("label")}
    # A device case the host clock timed (the device's profiling clock was unusable).
    host_clock = "timing=host" in labels and key[0] not in HOST_CASES
    return {"seconds": seconds, "bytes_per_second": med("bytes_per_second"),
            "items_per_second": med("items_per_second"), "passes": med("passes"), "host_clock": host_clock, "runs": len(runs), "median_of_repetitions": bool(medians)}


def ok(rec):
    return rec is not None and "error" not in rec and rec["seconds"] > 0


def fastest(cases, names, n):
    best = None
    for name in names:
        rec = cases.get((name, n))
        if ok(rec) and rec.get("bytes_per_second") and (best is None or rec["bytes_per_second"] > best[1]["bytes_per_second"]):
            best = (name, rec)
    return best


def copy_reference(cases, n, bytes_per_op):
    """(copy name, copy n, record): the fastest copy at n, else at the size of nearest traffic."""
    at_n = fastest(cases, COPIES, n)
    if at_n:
        return at_n[0], n, at_n[1]
    sizes = sorted({k[1] for k in cases if k[0] in COPIES})
    if not sizes or not bytes_per_op:
        return None
    m = min(sizes, key=lambda s: abs(math.log(8.0 * s) - math.log(bytes_per_op)))
    ref = fastest(cases, COPIES, m)
    return (ref[0], m, ref[1]) if ref else None


def figures(cases):
    """The derived figures of one run, as plain records (the --json output)."""
    out = {"copy_fraction": [], "radix_bound": [], "speedups": [], "failed": []}
    for (name, n), rec in sorted(cases.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        if not ok(rec):
            out["failed"].append({"case": name, "n": n, "error": rec.get("error", "no time")})
            continue
        if name in COPIES or not rec.get("bytes_per_second"):
            continue
        ref = copy_reference(cases, n, rec["bytes_per_second"] * rec["seconds"])
        if ref:
            out["copy_fraction"].append({
                "case": name, "n": n, "bytes_per_second": rec["bytes_per_second"], "copy": ref[0], "copy_n": ref[1],
                "copy_bytes_per_second": ref[2]["bytes_per_second"],
                "fraction": rec["bytes_per_second"] / ref[2]["bytes_per_second"], "host_clock": rec["host_clock"]})
    sizes = sorted({k[1] for k in cases})
    for n in sizes:
        radix_bound(cases, n, out["radix_bound"])
        for ours, peers in PEERS.items():
            for peer in peers:
                a, b = cases.get((ours, n)), cases.get((peer, n))
                if ok(a) and ok(b):
                    out["speedups"].append({"case": ours, "peer": peer, "n": n, "speedup": b["seconds"] / a["seconds"],
                                            "host_clock": a["host_clock"] or b["host_clock"]})
    return out


def radix_bound(cases, n, sink):
    sort = cases.get(("radix_sort.u32", n))
    copy = fastest(cases, DEVICE_COPIES, n)
    if not ok(sort) or not copy:
        return
    t_copy = copy[1]["seconds"]
    passes_used = int(sort["passes"]) if sort.get("passes") else None
    for p in sorted({4, passes_used} - {None}):
        bound = n / (p * t_copy)  # keys per second
        sink.append({"n": n, "passes": p, "bound_keys_per_second": bound, "copy": copy[0], "copy_seconds": t_copy,
                     "fraction": (n / sort["seconds"]) / bound, "passes_used": p == passes_used})


def size_label(n):
    if n > 0 and n & (n - 1) == 0:
        return f"2^{n.bit_length() - 1}"
    return "1080p" if n == 1920 * 1080 else str(n)


def pct(x):
    return f"{100 * x:.3g}%"


def times(x):
    return f"{x:.3g}x"


def mark(host):
    return " (host clock)" if host else ""


def print_figures(title, cases, figs, context):
    print(f"## {title}\n")
    for key in ("device", "tuning", "host_threads", "date"):
        if key in context:
            print(f"- {key}: {context[key]}")
    print("\n| n | case | time | GB/s | of the fastest copy |\n|---|---|---|---|---|")
    for f in figs["copy_fraction"]:
        rec = cases[(f["case"], f["n"])]
        at = "" if f["copy_n"] == f["n"] else f" at {size_label(f['copy_n'])}"
        print(f"| {size_label(f['n'])} | {f['case']}{mark(f['host_clock'])} | {format_time(rec['seconds'])} | "
              f"{f['bytes_per_second'] * 1e-9:.3g} | {pct(f['fraction'])} "
              f"({f['copy']}{at}, {f['copy_bytes_per_second'] * 1e-9:.3g} GB/s) |")
    print("\n| n | radix_sort.u32 | passes | bound Mkeys/s | of the bound |\n|---|---|---|---|---|")
    for r in figs["radix_bound"]:
        which = "passes used" if r["passes_used"] else "reference"
        print(f"| {size_label(r['n'])} | n / ({r['passes']} x {format_time(r['copy_seconds'])}, {r['copy']}) | "
              f"{r['passes']} ({which}) | {r['bound_keys_per_second'] * 1e-6:.4g} | {pct(r['fraction'])} |")
    print("\n| n | ours | peer | speed-up |\n|---|---|---|---|")
    for s in figs["speedups"]:
        print(f"| {size_label(s['n'])} | {s['case']} | {s['peer']} | {times(s['speedup'])}{mark(s['host_clock'])} |")
    for f in figs["failed"]:
        print(f"\nFAILED {f['case']}/{f['n']}: {f['error']}")
    print()


def format_time(seconds):
    return f"{seconds * 1e3:.3f} ms" if seconds < 10 else f"{seconds:.2f} s"


def compare(old_path, new_path):
    old, old_ctx = load(old_path)
    new, new_ctx = load(new_path)
    print(f"## {os.path.basename(old_path)} (old) vs {os.path.basename(new_path)} (new)\n")
    print(f"- old: {old_ctx.get('device', '?')}\n- new: {new_ctx.get('device', '?')}\n")
    print("| case | n | old | new | new / old |\n|---|---|---|---|---|")
    for key in sorted(set(old) | set(new), key=lambda k: (k[1], k[0])):
        a, b = old.get(key), new.get(key)
        ta = format_time(a["seconds"]) + mark(a["host_clock"]) if ok(a) else (a or {}).get("error", "-")[:40]
        tb = format_time(b["seconds"]) + mark(b["host_clock"]) if ok(b) else (b or {}).get("error", "-")[:40]
        ratio = f"{b['seconds'] / a['seconds']:.2f}" if ok(a) and ok(b) else "-"
        print(f"| {key[0]} | {size_label(key[1])} | {ta} | {tb} | {ratio} |")
    fo, fn = figures(old), figures(new)
    print("\n| n | ours | peer | speed-up old | speed-up new |\n|---|---|---|---|---|")
    index = {(s["case"], s["peer"], s["n"]): s["speedup"] for s in fo["speedups"]}
    for s in fn["speedups"]:
        before = index.get((s["case"], s["peer"], s["n"]))
        print(f"| {size_label(s['n'])} | {s['case']} | {s['peer']} | "
              f"{'-' if before is None else times(before)} | {times(s['speedup'])} |")
    print("\n| n | case | of the fastest copy, old | new |\n|---|---|---|---|")
    index = {(f["case"], f["n"]): f["fraction"] for f in fo["copy_fraction"]}
    for f in fn["copy_fraction"]:
        before = index.get((f["case"], f["n"]))
        print(f"| {size_label(f['n'])} | {f['case']} | {'-' if before is None else pct(before)} | {pct(f['fraction'])} |")
    return fo, fn


def run_standard(old_path, new_path):
    """Google Benchmark's compare.py on the same two files, with a python that has scipy."""
    if not os.path.exists(STANDARD_COMPARE):
        print(f"\n{STANDARD_COMPARE} is missing: install libbenchmark-tools (and python3-scipy)")
        return 0
    for py in (sys.executable, "/usr/bin/python3", shutil.which("python3")):
        if py and subprocess.run([py, "-c", "import scipy"], capture_output=True).returncode == 0:
            print(f"\n$ {STANDARD_COMPARE} benchmarks {old_path} {new_path}", flush=True)
            return subprocess.run([py, STANDARD_COMPARE, "--no-color", "benchmarks", old_path, new_path]).returncode
    print("\ncompare.py needs scipy: install python3-scipy")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", nargs="?", help="Google Benchmark JSON of manylights-kernel-bench")
    ap.add_argument("--json", help="also write the derived figures to this file")
    ap.add_argument("--compare", nargs=2, metavar=("OLD", "NEW"), help="two runs side by side")
    ap.add_argument("--standard", action="store_true", help="with --compare: then run Google Benchmark's compare.py")
    args = ap.parse_args(argv)
    if bool(args.run) == bool(args.compare):
        ap.error("give one run, or --compare OLD NEW")
    try:
        if args.compare:
            fo, fn = compare(*args.compare)
            doc = {"old": fo, "new": fn}
        else:
            cases, context = load(args.run)
            if not cases:
                raise InputError(f"{args.run}: no manylights-kernel-bench cases ('<case>/<n>') in it")
            doc = figures(cases)
            print_figures(context.get("device", args.run), cases, doc, context)
    except InputError as e:
        sys.stderr.write(f"kernel_bench_ratios.py: {e}\n")
        return 2
    if args.json:
        with open(args.json, "w") as f:
            json.dump(doc, f, indent=2)
    if args.compare and args.standard:
        return run_standard(*args.compare)
    return 0


if __name__ == "__main__":
    sys.exit(main())
