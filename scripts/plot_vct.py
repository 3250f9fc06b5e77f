#!/usr/bin/env python3
"""Error against time of voxel cone tracing: the Pareto front users pick a setting from.

  plot_vct.py FRAME_JSON --out DIR [--load LOAD_TXT]

Reads the records of `manylights-vct-bench --frame --json FRAME_JSON` (one per
scene x light set x voxels x isotropic/anisotropic x cone count: every vct pass
in ms and `gi_rel_rmse` against the Embree reference, and, where the record
has it, `gi_rel_rmse_corrected`: the same without the reference's own noise,
which is what is plotted then) and writes into DIR:
  vct_error_vs_time.png  per scene and light count (records with `lights`,
                         from --frame-lights sweeps), relative RMSE of the indirect image against
                         the per-frame VCT time (every pass but the one-off
                         voxelization), colour = volume kind, marker = grid
                         size, label = cone count, the Pareto front as a line;
  vct_pareto.md          the front's settings as a table.
"""
import argparse
import json
import os
import sys

PER_FRAME = ("vct-lists", "vct-inject", "vct-mips", "vct-textures", "vct-trace", "vct-upsample")
REQUIRED = ("scene", "voxels", "anisotropic", "cones", "gi_rel_rmse") + PER_FRAME


def load(path):
    with open(path) as f:
        recs = json.load(f)
    if not isinstance(recs, list) or not recs:
        sys.exit(f"plot_vct.py: {path}: expected the non-empty record list of manylights-vct-bench --frame --json")
    for i, r in enumerate(recs):
        missing = [k for k in REQUIRED if k not in r]
        if missing:
            sys.exit(f"plot_vct.py: {path}: record {i} lacks {', '.join(missing)} (not a --frame sweep?)")
    return recs


def frame_ms(r):
    return sum(r[p] for p in PER_FRAME)


def error(r):
    """The noise-corrected error where the sweep wrote one (older records: the raw one)."""
    c = r.get("gi_rel_rmse_corrected")
    return c if c is not None and c >= 0 else r["gi_rel_rmse"]


def pareto(recs):
    """Records no other record beats in both time and error, fastest first."""
    front, best = [], float("inf")
    for r in sorted(recs, key=lambda r: (frame_ms(r), error(r))):
        if error(r) < best:
            front.append(r)
            best = error(r)
    return front


def group(r):
    """A panel of the plot: the scene, and its light count when the record has one."""
    return f"{r['scene']}, {r['lights']} lights" if "lights" in r else r["scene"]


def plot(by_scene, out_png, load_line):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # one line, not a traceback: the fix is a package
        sys.stderr.write("plot_vct.py: matplotlib is missing; install python3-matplotlib\n")
        sys.exit(2)
    markers = {32: "o", 64: "s", 128: "^", 256: "D"}
    cols = min(2, len(by_scene))
    rows = (len(by_scene) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6 * cols, 4.5 * rows), squeeze=False)
    for ax in axes.flat[len(by_scene):]:
        ax.set_visible(False)
    for ax, (scene, recs) in zip(axes.flat, sorted(by_scene.items())):
        for r in recs:
            colour = "tab:blue" if r["anisotropic"] else "tab:orange"
            ax.scatter(frame_ms(r), error(r), c=colour, marker=markers.get(r["voxels"], "x"), s=36)
            ax.annotate(str(r["cones"]), (frame_ms(r), error(r)), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
        front = pareto(recs)
        ax.plot([frame_ms(r) for r in front], [error(r) for r in front], "k--", lw=1, label="Pareto front")
        for kind, colour in (("anisotropic", "tab:blue"), ("isotropic", "tab:orange")):
            ax.scatter([], [], c=colour, label=kind)
        for edge, m in markers.items():
            if any(r["voxels"] == edge for r in recs):
                ax.scatter([], [], c="grey", marker=m, label=f"{edge}^3")
        times = [frame_ms(r) for r in recs]
        if max(times) > 10 * min(times):  # a log axis within one decade has no labelled tick
            ax.set_xscale("log")
        ax.set_xlabel("VCT time per frame, ms (all passes but voxelization)")
        corrected = all(r.get("gi_rel_rmse_corrected") is not None for r in recs)
        ax.set_ylabel("relative RMSE of the indirect image" + (" (reference noise out)" if corrected else ""))
        ax.set_title(f"{scene} (labels: cone count)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    if load_line:
        fig.text(0.01, 0.01, "load: " + " / ".join(l.strip() for l in load_line.splitlines()), fontsize=7)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(out_png, dpi=110)


def write_table(by_scene, out_md):
    corrected = all(r.get("gi_rel_rmse_corrected") is not None for rs in by_scene.values() for r in rs)
    err = "rel RMSE (reference noise out)" if corrected else "rel RMSE"
    lines = [f"| scene | voxels | volume | cones | VCT ms/frame | {err} | MB |", "|---|---|---|---:|---:|---:|---:|"]
    for scene, recs in sorted(by_scene.items()):
        for r in pareto(recs):
            lines.append(f"| {scene} | {r['voxels']}^3 | {'aniso' if r['anisotropic'] else 'iso'} | {r['cones']} | "
                         f"{frame_ms(r):.1f} | {error(r):.4f} | {r.get('voxel_bytes', 0) / 1e6:.1f} |")
    with open(out_md, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("frame_json")
    ap.add_argument("--out", required=True)
    ap.add_argument("--load", help="a file with the machine's load (uptime) during the run, printed on the plot")
    a = ap.parse_args()
    by_scene = {}
    for r in load(a.frame_json):
        by_scene.setdefault(group(r), []).append(r)
    os.makedirs(a.out, exist_ok=True)
    load_line = open(a.load).read().strip() if a.load else ""
    write_table(by_scene, os.path.join(a.out, "vct_pareto.md"))
    plot(by_scene, os.path.join(a.out, "vct_error_vs_time.png"), load_line)
    print(f"wrote {a.out}/vct_error_vs_time.png and {a.out}/vct_pareto.md")


if __name__ == "__main__":
    main()
