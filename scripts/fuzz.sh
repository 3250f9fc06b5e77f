#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/, clang, build-fuzz/) and runs each
# target for a fixed time, then prints per target the executions and crashes.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   default 60 s, every target
# Targets: gltf lights camera suite cli. Seeds: fuzz/corpus/<target>/ plus the
# small files of data/; the grown corpus stays in build-fuzz/corpus/<target>/
# (so later runs start where this one stopped). A crash, hang (> 10 s per
# input) or OOM (> 2 GB) leaves its input in build-fuzz/artifacts/<target>/;
# fix the loader, then add the input under tests/fuzz/fuzz_regressions/<target>/
# (tests/fuzz/fuzz_regression_test.cpp replays them). Exit 1 if anything crashed.
# Uses ccache when installed. Env: FUZZ_JOBS (build jobs, default nproc),
# FUZZ_PARALLEL (targets fuzzed at once, default nproc).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
seconds="${1:-60}"
shift || true
targets=("$@")
((${#targets[@]})) || targets=(gltf lights camera suite cli)
if ! [[ "$seconds" =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz.sh: SECONDS_PER_TARGET must be a positive integer (got '$seconds')" >&2
  exit 2
fi
for t in "${targets[@]}"; do
  [[ -d "fuzz/corpus/$t" ]] || { echo "fuzz.sh: unknown target '$t' (gltf lights camera suite cli)" >&2; exit 2; }
done
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (scripts/packages.txt: clang, libclang-rt-14-dev)" >&2; exit 2; }

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
SECONDS=0
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMANYLIGHTS_BUILD_FUZZ=ON \
      -DMANYLIGHTS_BUILD_TESTS=OFF -DMANYLIGHTS_BUILD_BENCH=OFF -DMANYLIGHTS_WERROR=ON "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"${FUZZ_JOBS:-$(nproc)}" --target "${targets[@]/#/fuzz-}" >/dev/null
echo "== fuzz build: ${SECONDS}s; ${seconds}s per target =="

# Small files of data/ that each target reads (the default scene's .glb and
# light file are too large to mutate usefully; fuzz/corpus has small versions).
seed_files() {
  case "$1" in
    lights) echo data/default/light_volumes.json ;;
    camera) echo data/default/camera.json ;;
  esac
}

# fuzz_one TARGET: one libFuzzer run; its table row goes to build-fuzz/fuzz-TARGET.row,
# exit 1 when it crashed.
fuzz_one() {
  local t="$1"
  local corpus="build-fuzz/corpus/$t" seeds="build-fuzz/seeds/$t" artifacts="build-fuzz/artifacts/$t"
  mkdir -p "$corpus" "$seeds" "$artifacts"
  for f in $(seed_files "$t"); do cp "$f" "$seeds/"; done
  local log="build-fuzz/fuzz-$t.log"
  : >"$log.start"  # artifacts newer than this marker are this run's
  local rc=0
  # close_fd_mask=3: the loaders' warnings stay quiet; libFuzzer's and the
  # sanitizers' reports still reach the log.
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "build-fuzz/fuzz/fuzz-$t" "$corpus" "fuzz/corpus/$t" "$seeds" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -close_fd_mask=3 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1 || rc=$?
  local runs found
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  [[ -n "$runs" ]] || runs="$(sed -n 's/^#\([0-9]*\).*/\1/p' "$log" | tail -1)"
  found="$(find "$artifacts" -type f -newer "$log.start" 2>/dev/null | tr '\n' ' ')"
  {
    printf '%-8s %12s %8s %8s  %s\n' "$t" "${runs:-?}" "$(( ${runs:-0} / seconds ))" "$((rc != 0))" "${found:--}"
    if ((rc != 0)); then
      grep -m1 -E '^==[0-9]+==ERROR|runtime error|deadly signal|ALARM|out-of-memory|uncaught' "$log" | sed 's/^/    /' || true
    fi
  } >"build-fuzz/fuzz-$t.row"
  return $((rc != 0))
}

# The targets run FUZZ_PARALLEL at a time (default nproc; each is one process
# on one core), so a CI pass takes ceil(5 / cores) x SECONDS.
parallel="${FUZZ_PARALLEL:-$(nproc)}"
[[ "$parallel" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: FUZZ_PARALLEL must be a positive integer (got '$parallel')" >&2; exit 2; }
failed=0
printf '%-8s %12s %8s %8s  %s\n' target executions exec/s crashes artifacts
for ((b = 0; b < ${#targets[@]}; b += parallel)); do
  pids=()
  for t in "${targets[@]:b:parallel}"; do
    fuzz_one "$t" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  for t in "${targets[@]:b:parallel}"; do cat "build-fuzz/fuzz-$t.row"; done
done
echo "== fuzz: ${SECONDS}s in all; logs in build-fuzz/fuzz-<target>.log =="
exit "$failed"
