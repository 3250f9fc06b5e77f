#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite on this machine's
# OpenCL device (PoCL on CPU-only machines) and headless GL (Mesa llvmpipe),
# the GPU-shape kernel tests under Oclgrind, a short fuzzing pass, then the
# unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
# Prints one timing line per step and the total.
#   scripts/test.sh            everything
#   scripts/test.sh --no-asan  skip the sanitizer pass
# Env: OCLGRIND=0 skips the Oclgrind step, FUZZ_SECONDS=0 the fuzzing pass
# (default 20 s per target).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="$(nproc)"
start=$(date +%s)
step() { echo "== $1: ${SECONDS}s =="; SECONDS=0; }

# ccache when installed (as scripts/fuzz.sh): free on a fresh machine, and a
# CI machine that keeps ~/.cache/ccache rebuilds only what changed.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

# The suite as one gtest process per core (gtest sharding, logs in
# <build>/tests-shard<i>.log), not one process per test as ctest runs it: each
# process loads ~270 shared libraries and opens its own CL and GL contexts and
# kernel cache, which cost more than most tests (`ctest` still runs them one
# by one). A shard that crashes names its log; every shard's summary is printed.
#   run_shards BUILD_DIR ENV_ASSIGNMENTS
run_shards() {
  local dir="$1" envs="$2" pids=() failed=0 i
  for ((i = 0; i < jobs; ++i)); do
    env $envs GTEST_TOTAL_SHARDS="$jobs" GTEST_SHARD_INDEX="$i" \
      timeout 1800 "$dir/tests/manylights-tests" --gtest_brief=1 >"$dir/tests-shard$i.log" 2>&1 &
    pids+=($!)
  done
  for ((i = 0; i < jobs; ++i)); do
    if ! wait "${pids[$i]}"; then
      echo "== shard $i failed ($dir/tests-shard$i.log) ==" >&2
      grep -E '^\[  FAILED  \]' "$dir/tests-shard$i.log" >&2 || tail -60 "$dir/tests-shard$i.log" >&2
      failed=1
    fi
    grep -E '^\[  (PASSED|SKIPPED|FAILED)  \] [0-9]+ test' "$dir/tests-shard$i.log" | sed "s/^/shard $i: /" || true
  done
  ((failed == 0))
}

SECONDS=0
scripts/setup.sh --no-build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMANYLIGHTS_WERROR=ON "${launcher[@]}" >/dev/null
cmake --build build -j"$jobs"
step "build (Release)"
run_shards build ""
step "tests (Release)"

# The GPU-shape kernel tests under the Oclgrind device simulator (races,
# uninitialized values, out-of-bounds accesses, API errors), at small sizes.
if [[ "${OCLGRIND:-1}" != 0 ]]; then
  scripts/oclgrind.sh --ci
  step "Oclgrind"
fi

# A short fuzzing pass over the loaders and the command line (FUZZ_SECONDS per
# target, 0 skips it); longer runs: scripts/fuzz.sh 300.
if [[ "${FUZZ_SECONDS:-20}" != 0 ]]; then
  scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
  step "fuzz (build + run)"
fi

if [[ "${1:-}" != "--no-asan" ]]; then
  # -O1 and line tables (-g1) rather than RelWithDebInfo's -O2 -g: half the
  # compile time (measured per file: 17.4 vs 8.3 CPU-s for gl/FrameRenderer.cpp),
  # and a report still names file:line.
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
        -DMANYLIGHTS_SANITIZE=ON -DMANYLIGHTS_WERROR=ON -DMANYLIGHTS_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
  cmake --build build-asan -j"$jobs" --target manylights manylights-tests
  step "build (ASan + UBSan)"
  # Leak checking is off: the OpenCL ICD loader, PoCL and Mesa keep process-lifetime
  # allocations that LeakSanitizer reports; memory errors and UB still abort.
  run_shards build-asan "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1"
  step "tests (ASan + UBSan)"
fi
echo "== total: $(($(date +%s) - start))s =="
