#!/usr/bin/env python3
"""Thesis-style figures from `manylights bench` (and `compare-reference`) JSON.

    plot_bench.py BENCH.json [--out DIR] [--compare COMPARE.json] [--title TEXT]

Writes into DIR (default: the JSON's folder):
  frames_light_evaluations.png  light evaluations per frame along the camera path, one
                                line per technique variant, the exact lower bound dashed;
                                one panel per (light set, resolution)
  frames_time.png               frame time (sum of device passes) per frame (timed runs)
  mean_vs_lights.png            mean per frame against the number of lights (per resolution)
  mean_vs_resolution.png        mean per frame against the resolution (per light set)
  passes.png                    mean time per pass, stacked, per run (timed runs)
  compare_frames.png            with --compare: ours vs the thesis per frame, per series
  compare_ratios.png            with --compare: technique ratios, ours vs the thesis

Needs matplotlib (Debian: python3-matplotlib); nothing else.
"""
import argparse
import json
import math
import os
import sys
from collections import OrderedDict, defaultdict

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:  # pragma: no cover - the message is the point
    sys.stderr.write("plot_bench.py: matplotlib is missing; install python3-matplotlib\n")
    sys.exit(2)


def variant_of(rec):
    """The run label without light set and size: 'tiled-deferred[tile=16]'."""
    params = rec.get("params") or {}
    label = rec["technique"]
    if params:
        label += "[" + ",".join(f"{k}={v}" for k, v in params.items()) + "]"
    return label


def mean(values):
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def colours(labels):
    cmap = plt.get_cmap("tab10" if len(labels) <= 10 else "tab20")
    return {label: cmap(i % cmap.N) for i, label in enumerate(labels)}


def grid(n):
    cols = min(n, 2)
    rows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(7.0 * cols, 3.8 * rows), squeeze=False)
    flat = [ax for row in axes for ax in row]
    for ax in flat[n:]:
        ax.set_visible(False)
    return fig, flat


def save(fig, out_dir, name, written):
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    written.append(path)


def per_frame(records, key, ylabel, title, out_dir, name, written, bound=False):
    recs = [r for r in records if r.get(key) is not None]
    if not recs:
        return
    groups = OrderedDict()
    for r in recs:
        groups.setdefault((r["lights"], r["light_count"], r["width"], r["height"]), []).append(r)
    variants = list(OrderedDict((variant_of(r), None) for r in recs))
    col = colours(variants)
    fig, axes = grid(len(groups))
    for ax, ((lights, count, w, h), rs) in zip(axes, groups.items()):
        by_variant = OrderedDict()
        for r in rs:
            by_variant.setdefault(variant_of(r), []).append(r)
        for v, vr in by_variant.items():
            vr.sort(key=lambda r: r["frame"])
            ax.plot([r["frame"] for r in vr], [r[key] for r in vr], label=v, color=col[v], lw=1.2,
                    marker="." if len(vr) < 40 else None)
        if bound:
            first = next(iter(by_variant.values()))
            ax.plot([r["frame"] for r in first], [r["lower_bound"] for r in first], "k--", lw=1.0,
                    label="exact lower bound")
        ax.set_title(f"{lights} ({count} lights), {w}x{h}", fontsize=10)
        ax.set_xlabel("frame")
        ax.set_ylabel(ylabel)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title)
    save(fig, out_dir, name, written)


def summaries_by(records, key):
    """(variant, lights, count, w, h) -> mean of key over frames."""
    acc = defaultdict(list)
    for r in records:
        acc[(variant_of(r), r["lights"], r["light_count"], r["width"], r["height"])].append(r.get(key))
    return {k: mean(v) for k, v in acc.items()}


def mean_vs(records, axis, out_dir, name, written):
    counted = any(r.get("light_evaluations") is not None for r in records)
    timed = any(r.get("passes_total_ms") is not None for r in records)
    metrics = ([("light_evaluations", "light evaluations per frame")] if counted else []) + \
              ([("passes_total_ms", "frame time (ms, device passes)")] if timed else [])
    if not metrics:
        return
    evals = summaries_by(records, "light_evaluations")
    bounds = summaries_by(records, "lower_bound")
    times = summaries_by(records, "passes_total_ms")
    # Panels: one per resolution (mean vs lights) or per light set (mean vs resolution).
    if axis == "lights":
        panels = OrderedDict(((r["width"], r["height"]), None) for r in records)
        xkey = lambda k: k[2]
        panel_of = lambda k: (k[3], k[4])
        panel_title = lambda p: f"{p[0]}x{p[1]}"
        xlabel = "number of lights"
    else:
        panels = OrderedDict(((r["lights"], r["light_count"]), None) for r in records)
        xkey = lambda k: k[3] * k[4]
        panel_of = lambda k: (k[1], k[2])
        panel_title = lambda p: f"{p[0]} ({p[1]} lights)"
        xlabel = "pixels"
    variants = list(OrderedDict((variant_of(r), None) for r in records))
    col = colours(variants)
    fig, axes = grid(len(panels) * len(metrics))
    i = 0
    for metric, ylabel in metrics:
        source = evals if metric == "light_evaluations" else times
        for p in panels:
            ax = axes[i]
            i += 1
            for v in variants:
                pts = sorted((xkey(k), val) for k, val in source.items()
                             if k[0] == v and panel_of(k) == p and val is not None)
                if pts:
                    ax.plot([x for x, _ in pts], [y for _, y in pts], marker="o", label=v, color=col[v])
            if metric == "light_evaluations":
                pts = {}
                for k, val in bounds.items():
                    if panel_of(k) == p and val is not None:
                        pts[xkey(k)] = val
                if pts:
                    xs = sorted(pts)
                    ax.plot(xs, [pts[x] for x in xs], "k--", marker="x", label="exact lower bound")
            ax.set_title(panel_title(p), fontsize=10)
            ax.set_xlabel(xlabel)
            ax.set_ylabel("mean " + ylabel)
            if metric == "light_evaluations":
                # Brute force is 10-100x the rest: a log axis keeps the culled techniques apart.
                ax.set_yscale("log")
            else:
                ax.set_ylim(bottom=0)
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=7)
    fig.suptitle("mean per frame vs " + ("number of lights" if axis == "lights" else "resolution"))
    save(fig, out_dir, name, written)


def passes_plot(doc, out_dir, written):
    sums = [s for s in doc.get("summaries", []) if s.get("passes")]
    if not sums:
        return
    names = list(OrderedDict((n, None) for s in sums for n in s["passes"]))
    col = colours(names)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.55 * len(sums) + 3), 4.5))
    bottoms = [0.0] * len(sums)
    for n in names:
        vals = [s["passes"].get(n, {}).get("mean", 0.0) for s in sums]
        ax.bar(range(len(sums)), vals, bottom=bottoms, label=n, color=col[n])
        bottoms = [b + v for b, v in zip(bottoms, vals)]
    ax.set_xticks(range(len(sums)))
    ax.set_xticklabels([s["run"] for s in sums], rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("mean time per frame (ms)")
    ax.set_title("time per pass")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")
    save(fig, out_dir, "passes.png", written)


def compare_plots(cmp, out_dir, written):
    series = [s for s in cmp.get("series", []) if s.get("frames")]
    if series:
        fig, axes = grid(len(series))
        for ax, s in zip(axes, series):
            ax.plot(s["frames"], s["thesis"], label="thesis", color="tab:gray", lw=1.2)
            ax.plot(s["frames"], s["ours"], label="ours", color="tab:blue", lw=1.2)
            ax.plot(s["frames"], s["lower_bound"], "k--", lw=0.9, label="exact lower bound (ours)")
            matched = set(cmp.get("matched_frames", []))
            off = [f for f in s["frames"] if f not in matched]
            if off and len(off) < len(s["frames"]):
                ys = [o for f, o in zip(s["frames"], s["ours"]) if f not in matched]
                ax.scatter(off, ys, s=8, color="tab:red", zorder=3, label="coverage differs (missing mesh)")
            ax.set_title(f"{s['series']}: {s['label']}", fontsize=9)
            ax.set_xlabel("frame")
            ax.set_ylabel("light evaluations")
            ax.set_ylim(bottom=0)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
        fig.suptitle(f"{cmp.get('scene', '')}: ours vs the thesis per frame (naive x {cmp.get('naive_scale', 10):g})")
        save(fig, out_dir, "compare_frames.png", written)
    ratios = cmp.get("ratios", [])
    if ratios:
        fig, ax = plt.subplots(figsize=(max(6.0, 0.7 * len(ratios) + 2), 4.2))
        xs = range(len(ratios))
        ours = [r["ours"]["mean"] for r in ratios]
        theirs = [r["thesis"]["mean"] for r in ratios]
        ax.bar([x - 0.2 for x in xs], ours, width=0.4, label="ours", color="tab:blue")
        ax.bar([x + 0.2 for x in xs], theirs, width=0.4, label="thesis", color="tab:gray")
        ax.set_xticks(list(xs))
        ax.set_xticklabels([f"{r['ratio']}\ntile {r['tile']}" for r in ratios], fontsize=7)
        ax.set_ylabel("mean per-frame ratio")
        ax.set_title("technique ratios")
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=8)
        save(fig, out_dir, "compare_ratios.png", written)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bench_json", nargs="?", help="JSON written by `manylights bench --json`")
    ap.add_argument("--out", help="output folder (default: the JSON's folder)")
    ap.add_argument("--compare", help="JSON written by `manylights compare-reference --json`")
    args = ap.parse_args(argv)
    if not args.bench_json and not args.compare:
        ap.error("give a bench JSON and/or --compare")
    out_dir = args.out or os.path.dirname(os.path.abspath(args.bench_json or args.compare))
    os.makedirs(out_dir, exist_ok=True)
    written = []
    if args.bench_json:
        with open(args.bench_json) as f:
            doc = json.load(f)
        if doc.get("schema") != "manylights-bench/1":
            sys.stderr.write(f"plot_bench.py: {args.bench_json}: not a manylights bench JSON\n")
            return 2
        recs = doc.get("records", [])
        per_frame(recs, "light_evaluations", "light evaluations", "light evaluations per frame", out_dir,
                  "frames_light_evaluations.png", written, bound=True)
        per_frame(recs, "passes_total_ms", "ms (device passes)", "frame time per frame", out_dir,
                  "frames_time.png", written)
        mean_vs(recs, "lights", out_dir, "mean_vs_lights.png", written)
        mean_vs(recs, "resolution", out_dir, "mean_vs_resolution.png", written)
        passes_plot(doc, out_dir, written)
    if args.compare:
        with open(args.compare) as f:
            compare_plots(json.load(f), out_dir, written)
    for p in written:
        print(f"plot_bench.py: wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
