#!/usr/bin/env python3
"""Table and log-log plot of the constant-density scale sweep (scripts/scale_sweep.sh).

  plot_scale.py TIMING_JSON [--counts COUNTS_JSON] [--load LOAD_TXT] --out DIR

Reads `manylights bench` JSON (one camera frame per run) and writes into DIR:
  scale.md   per technique and light count: assignment time (the frame's device
             and host passes without the GL rasterisation of depth: gbuffer,
             depth-prepass), hashed's one-off host build, structure memory, the
             exact lower bound per covered pixel and, from COUNTS_JSON, light
             evaluations per covered pixel; then the per-light growth from 16k
             to 1M lights, (metric(1M) / 1M) / (metric(16k) / 16k): 1.0 is
             linear, the issue's target is within 2x.
             Rows are runs (technique and swept parameters): the sweep runs the
             automatic tiles beside the previous defaults (tile=16 minmax,
             cluster_tile=32), and "Against the previous defaults" gives, per
             light count, each pair's evaluations / bound and the assignment
             time of the automatic run over the fixed one's (same bench run).
  scale.png  log-log assignment time (hashed: its build) and memory vs N, with a
             dashed linear-growth guide, and light evaluations / exact lower
             bound vs N per run.
"""
import argparse
import json
import os
import sys

RASTER_PASSES = ("gbuffer", "depth-prepass")  # GL depth rasterisation: the same for every N


def records(path):
    with open(path) as f:
        doc = json.load(f)
    return doc.get("meta", {}), doc["records"]


def assignment_ms(rec):
    if rec.get("passes_total_ms") is None:
        return None
    return rec["passes_total_ms"] - sum(rec["passes"].get(p, 0.0) for p in RASTER_PASSES)


def label(rec):
    """The run's technique and swept parameters, e.g. tiled-deferred[tile=16,tile_depth=minmax]."""
    return rec["run"].split(" ")[0]


def collect(timing, counts):
    """{run label: {N: row}}; one frame per run (several frames: the last wins)."""
    table = {}
    for r in timing:
        row = table.setdefault(label(r), {}).setdefault(r["light_count"], {})
        row["assign_ms"] = assignment_ms(r)
        row["build_ms"] = dict(r.get("technique_stats", {})).get("build ms")
        row["memory"] = r.get("memory_bytes")
        if r.get("lower_bound") is not None and r.get("covered_pixels"):
            row["bound_px"] = r["lower_bound"] / r["covered_pixels"]
    for r in counts:
        row = table.setdefault(label(r), {}).setdefault(r["light_count"], {})
        if r.get("light_evaluations") is not None and r.get("covered_pixels"):
            row["evals_px"] = r["light_evaluations"] / r["covered_pixels"]
            row["bound_px"] = r["lower_bound"] / r["covered_pixels"]
    return table


def time_metric(tech, row):
    """The cost that grows with N: hashed rebuilds on the host, the others assign per frame."""
    return row.get("build_ms") if tech.startswith("hashed") else row.get("assign_ms")


def per_light_ratio(table, tech, key, lo=16000, hi=1000000):
    rows = table[tech]
    if lo not in rows or hi not in rows:
        return None
    a = key(tech, rows[lo]) if callable(key) else rows[lo].get(key)
    b = key(tech, rows[hi]) if callable(key) else rows[hi].get(key)
    if not a or not b:
        return None
    return (b / hi) / (a / lo)


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def markdown(table, meta, load):
    out = ["# Constant-density scale sweep", ""]
    if meta:
        out += ["command: `%s`" % meta.get("command", "?"), "",
                "device: %s; GL: %s" % (meta.get("device", "?"), meta.get("gl", "?")), ""]
    if load:
        out += ["load: " + " / ".join(l.strip() for l in load), ""]
    out += ["| technique | lights | assignment ms | hashed build ms | memory MiB | bound / px | evals / px | evals / bound |",
            "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for tech in sorted(table):
        for n in sorted(table[tech]):
            r = table[tech][n]
            ratio = evals_over_bound(r)
            mem = r["memory"] / 2**20 if r.get("memory") is not None else None
            out.append("| %s | %d | %s | %s | %s | %s | %s | %s |" % (
                tech, n, fmt(r.get("assign_ms"), ".1f"), fmt(r.get("build_ms"), ".0f"), fmt(mem, ".1f"),
                fmt(r.get("bound_px"), ".2f"), fmt(r.get("evals_px"), ".2f"), fmt(ratio, ".2f")))
    out += previous_defaults(table)
    out += ["", "Per-light growth from 16k to 1M lights ((x(1M)/1M) / (x(16k)/16k); 1.0 = linear; target <= 2):", "",
            "| technique | time (hashed: build) | memory |", "|---|---:|---:|"]
    for tech in sorted(table):
        out.append("| %s | %s | %s |" % (tech, fmt(per_light_ratio(table, tech, time_metric), ".2f"),
                                         fmt(per_light_ratio(table, tech, "memory"), ".2f")))
    return "\n".join(out) + "\n"


def evals_over_bound(row):
    return row["evals_px"] / row["bound_px"] if row.get("evals_px") and row.get("bound_px") else None


def fixed_peer(run, table):
    """The automatic run's fixed-parameter peer: tile=auto -> tile=16 with minmax, cluster_tile=auto -> 32."""
    for auto, fixed in (("tile=auto,tile_depth=mask", "tile=16,tile_depth=minmax"),
                        ("cluster_tile=auto", "cluster_tile=32")):
        if auto in run and run.replace(auto, fixed) in table:
            return run.replace(auto, fixed)
    return None


def previous_defaults(table):
    out = ["", "Against the previous defaults (same bench run; time = assignment ms, automatic / fixed):", "",
           "| run | previous | lights | evals / bound | previous evals / bound | time ratio |",
           "|---|---|---:|---:|---:|---:|"]
    rows = 0
    for run in sorted(table):
        peer = fixed_peer(run, table)
        if not peer:
            continue
        for n in sorted(table[run]):
            a, b = table[run][n], table[peer].get(n, {})
            t = a["assign_ms"] / b["assign_ms"] if a.get("assign_ms") and b.get("assign_ms") else None
            out.append("| %s | %s | %d | %s | %s | %s |" % (run, peer, n, fmt(evals_over_bound(a), ".2f"),
                                                           fmt(evals_over_bound(b), ".2f"), fmt(t, ".2f")))
            rows += 1
    return out if rows else []


def plot_tightness(table, ax):
    # Forward and deferred variants keep the same lists: the deferred ones stand for both.
    for run in sorted(r for r in table if "-forward" not in r):
        pts = [(n, evals_over_bound(r)) for n, r in sorted(table[run].items())]
        pts = [(n, v) for n, v in pts if v]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=run,
                    linestyle="--" if "=16," in run or "=32" in run else "-")
    ax.axhline(1.0, color="k", linewidth=1)
    ax.set_xscale("log")
    ax.set_xlabel("lights (constant density)")
    ax.set_title("light evaluations / exact lower bound (deferred runs)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def plot(table, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # one line, not a traceback: the fix is a package
        sys.stderr.write("plot_scale.py: matplotlib is missing; install python3-matplotlib\n")
        sys.exit(2)
    plt.rcParams["axes.prop_cycle"] = plt.cycler(color=plt.get_cmap("tab20").colors)
    fig, axes = plt.subplots(1, 3, figsize=(18, 5.2))
    panels = [(axes[0], time_metric, "assignment time per frame, ms (hashed: host build)"),
              (axes[1], lambda t, r: (r.get("memory") or 0) / 2**20 or None, "structure memory, MiB")]
    plot_tightness(table, axes[2])
    for ax, metric, title in panels:
        firsts = []
        for tech in sorted(table):
            pts = [(n, metric(tech, r)) for n, r in sorted(table[tech].items())]
            pts = [(n, v) for n, v in pts if v]
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=tech)
            firsts.append(pts[0])
        if firsts:
            n0 = min(p[0] for p in firsts)
            y0 = max(p[1] for p in firsts if p[0] == n0)
            ns = sorted({n for t in table for n in table[t]})
            ax.plot(ns, [y0 * n / n0 for n in ns], "k--", linewidth=1, label="linear growth (ratio 1)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("lights (constant density)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("timing")
    ap.add_argument("--counts")
    ap.add_argument("--load")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    meta, timing = records(a.timing)
    counts = records(a.counts)[1] if a.counts else []
    table = collect(timing, counts)
    if not table:
        sys.exit("plot_scale.py: %s has no records" % a.timing)
    load = open(a.load).read().splitlines() if a.load else []
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "scale.md"), "w") as f:
        f.write(markdown(table, meta, load))
    plot(table, os.path.join(a.out, "scale.png"))
    print("wrote %s and %s" % (os.path.join(a.out, "scale.md"), os.path.join(a.out, "scale.png")))


if __name__ == "__main__":
    main()
