#!/usr/bin/env bash
# The thesis-suite results of docs/testbed.md in one command: on spaceship-indoor
# (the hashed-shading thesis's scene, with its light sets, 320x320, deferred
# counts), every registered technique is
#   1. compared frame by frame with the thesis's own light-calculation counts
#      (compare-reference: naive, tiled 8/16/32/64, clustered 8/16/32; 70 lights),
#   2. benchmarked over the thesis's light sets (70 .. 1890 lights) at 320x320:
#      light evaluations, exact lower bound, pass times, memory,
#   3. benchmarked over resolutions with the 1260-light set (the thesis's
#      resolution-sweep set),
# and the results land in OUT (default results/thesis-suite/): compare.{json,csv,md},
# bench_lights.{json,csv}, bench_resolution.{json,csv}, plots/, plots-resolution/
# and summary.md (the tables).
#
#   scripts/thesis_results.sh [SUITE] [options]
#     SUITE                 the thesis-suite folder (default ../shared/data/thesis-suite)
#     --step N              compare every N-th frame of 3..518 (default 1: all 516 frames)
#     --light-step N        light sweep every N-th frame (default 8)
#     --res-step N          resolution sweep every N-th frame (default 32)
#     --sizes LIST          resolution sweep sizes (default 320x320,640x640,960x960)
#     --out DIR             output folder (default results/thesis-suite)
#     --techniques LIST     restrict the benchmark to these techniques (default: all registered)
#     --skip-resolution     no resolution sweep
# Env: MANYLIGHTS_BIN (default build/manylights), MANYLIGHTS_PYTHON (python3 with matplotlib).
# The full default run renders about 7,000 frames; on a 2-core CPU with llvmpipe/PoCL
# that is hours. `--step 8 --light-step 32 --res-step 128` takes about half an hour there.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

suite="../shared/data/thesis-suite"
step=1
light_step=8
res_step=32
sizes="320x320,640x640,960x960"
out="results/thesis-suite"
techniques=""
skip_res=0
# shellcheck source=scripts/script_options.sh
source scripts/script_options.sh
declare -A value_opts=([--step]=step [--light-step]=light_step [--res-step]=res_step [--sizes]=sizes [--out]=out
                       [--techniques]=techniques)
declare -A flag_opts=([--skip-resolution]="skip_res=1")
positional=suite
parse_options "$0" 27 "$@"

bin="${MANYLIGHTS_BIN:-build/manylights}"
if [[ ! -x "$bin" ]]; then
  echo "thesis_results.sh: error: $bin not found; build first (scripts/setup.sh) or set MANYLIGHTS_BIN" >&2
  exit 2
fi
scene="$suite/scenes/spaceship-indoor"
reference="$suite/reference"
if [[ ! -d "$scene/geometry" || ! -d "$reference" ]]; then
  echo "thesis_results.sh: error: $suite is not the thesis suite (needs scenes/spaceship-indoor/ and reference/)" >&2
  exit 2
fi
find_plot_python "$0"
export MANYLIGHTS_PYTHON="$python"

tech_args=()
[[ -n "$techniques" ]] && tech_args=(--techniques "$techniques")
mkdir -p "$out"
cmdline="scripts/thesis_results.sh $suite --step $step --light-step $light_step"
((skip_res)) || cmdline+=" --res-step $res_step --sizes $sizes"
[[ -n "$techniques" ]] && cmdline+=" --techniques $techniques"
((skip_res)) && cmdline+=" --skip-resolution"
echo "== techniques: ${techniques:-every registered one}"
echo "== 1/3 compare-reference (70 lights, 320x320, every ${step}th frame)"
"$bin" compare-reference --reference "$reference" --suite "$scene" --allow-missing-meshes \
  --frames "3:518:$step" --json "$out/compare.json" --csv "$out/compare.csv" --markdown "$out/compare.md"

# The thesis's settings: 32x32 tiles for tiled and clustered in its final
# comparison, no tiled depth bounds, hashed node sizes relative to the corridor
# light radius 23 (0.5 x 23 = 11.5) with start depth 3, and no geometry mask
# (the thesis's future work A; on by default here).
params=(--param tile=32 --param tile_depth=none --param cluster_tile=32 --param node_size=11.5 --param start_depth=3
  --param geometry_mask=off)
echo "== 2/3 light sweep (thesis light sets, 320x320, every ${light_step}th frame)"
"$bin" bench --suite "$scene" --allow-missing-meshes --lights thesis "${tech_args[@]}" "${params[@]}" \
  --size 320x320 --frames "3:518:$light_step" --json "$out/bench_lights.json" --csv "$out/bench_lights.csv"
if ((skip_res == 0)); then
  echo "== 3/3 resolution sweep (1260 lights, $sizes, every ${res_step}th frame)"
  "$bin" bench --suite "$scene" --allow-missing-meshes --lights 1260 "${tech_args[@]}" "${params[@]}" \
    --sizes "$sizes" --frames "3:518:$res_step" --json "$out/bench_resolution.json" --csv "$out/bench_resolution.csv"
fi

echo "== plots and summary"
"$python" scripts/plot_bench.py "$out/bench_lights.json" --compare "$out/compare.json" --out "$out/plots"
if ((skip_res == 0)); then
  "$python" scripts/plot_bench.py "$out/bench_resolution.json" --out "$out/plots-resolution"
fi
"$python" scripts/thesis_summary.py --compare "$out/compare.json" --lights-bench "$out/bench_lights.json" \
  $( ((skip_res == 0)) && echo --resolution-bench "$out/bench_resolution.json") \
  --reference "$reference" --out "$out/summary.md" --command "$cmdline"
echo "== wrote $out/summary.md"
