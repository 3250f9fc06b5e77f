#!/usr/bin/env bash
# The constant-density scale sweep (issue 17): `manylights bench` on the
# default scene at 1920x1080 for N = 1k .. 1M generated lights at
# --light-density K (radius ~ N^(-1/3), about K lights per visible surface
# point), every registered technique. Two bench runs per sweep:
#   timing.json  --no-shading, counts + timing: per-pass times of the depth and
#                assignment passes, structure memory, the exact lower bound;
#                hashed's one-off host build time is its "build ms" statistic;
#   counts.json  shaded counting frames (--no-timing) of the techniques that keep
#                lists, for light evaluations per pixel (brute force evaluates
#                N per pixel: not rendered); skipped with --no-eval-counts.
# Tiled and clustered run with their automatic tiles (the defaults) beside the
# previous defaults in the same bench runs (--param tile=auto,16
# tile_depth=mask,minmax cluster_tile=auto,32; --no-peers: defaults only).
# Then scripts/plot_scale.py writes scale.md (table, the automatic tiles
# against the previous defaults, per-light ratios 16k -> 1M) and scale.png
# (log-log time and memory vs N with a linear-growth guide; evaluations /
# exact bound vs N).
#
#   scripts/scale_sweep.sh [--counts LIST] [--density K] [--size WxH] [--repeat R]
#                          [--node-size S] [--out DIR] [--no-eval-counts] [--no-peers]
#     --counts     light counts (default 1000,4000,16000,64000,256000,1000000)
#     --density    mean exact lower bound per covered pixel (default 8)
#     --size       resolution (default 1920x1080)
#     --repeat     timed renders per frame, median (default 3)
#     --node-size  hashed node size (default 0.5r, the renderer's)
#     --out        output folder (default results/scale)
#     --no-peers   only the defaults (no previous-default runs beside them)
# Env: MANYLIGHTS_BIN (default build/manylights), MANYLIGHTS_PYTHON (python3 with matplotlib).
# On 2 CPU cores (PoCL + llvmpipe) the default sweep takes about 30 minutes (15 with --no-peers).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

counts="1000,4000,16000,64000,256000,1000000"
density=8
size=1920x1080
repeat=3
node_size=0.5r
out="results/scale"
eval_counts=1
peers=1
# shellcheck source=scripts/script_options.sh
source scripts/script_options.sh
declare -A value_opts=([--counts]=counts [--density]=density [--size]=size [--repeat]=repeat
                       [--node-size]=node_size [--out]=out)
declare -A flag_opts=([--no-eval-counts]="eval_counts=0" [--no-peers]="peers=0")
positional=""
parse_options "$0" 30 "$@"
bin="${MANYLIGHTS_BIN:-build/manylights}"
find_plot_python "$0"
[[ -x "$bin" ]] || { echo "scale_sweep.sh: error: $bin not found (build the manylights target)" >&2; exit 2; }
mkdir -p "$out"

common=(--lights "$counts" --light-density "$density" --size "$size" --frames 0:0:1 --node-size "$node_size"
        --progress lines)
((peers)) && common+=(--param tile=auto,16 --param tile_depth=mask,minmax --param cluster_tile=auto,32)
echo "== load before: $(uptime)" | tee "$out/load.txt"
"$bin" bench "${common[@]}" --no-shading --repeat "$repeat" --warmup 1 --json "$out/timing.json" \
  --csv "$out/timing.csv" | tee "$out/timing.log"
if ((eval_counts)); then
  listed="tiled-forward,tiled-deferred,clustered-forward,clustered-deferred,hashed-forward,hashed-deferred"
  "$bin" bench "${common[@]}" --techniques "$listed" --no-timing --warmup 0 --json "$out/counts.json" \
    --csv "$out/counts.csv" | tee "$out/counts.log"
fi
echo "== load after: $(uptime)" | tee -a "$out/load.txt"
args=("$out/timing.json" --out "$out")
((eval_counts)) && args+=(--counts "$out/counts.json")
"$python" scripts/plot_scale.py "${args[@]}" --load "$out/load.txt"
