#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite on this machine's
# OpenCL device (PoCL on CPU-only machines) and headless GL (Mesa llvmpipe),
# the GPU-shape kernel tests under Oclgrind, a short fuzzing pass, then the
# unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer. The
# kernel tests and technique renders also run on Mesa rusticl.
# Prints one timing line per step and the total.
#   scripts/test.sh            everything
#   scripts/test.sh --no-asan  skip the sanitizer pass
# Env: OCLGRIND=0 skips the Oclgrind step, RUSTICL=0 the rusticl step, FUZZ_SECONDS=0 the fuzzing pass
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

# shellcheck source=lib/shards.sh
source scripts/lib/shards.sh

SECONDS=0
scripts/setup.sh --no-build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMANYLIGHTS_WERROR=ON "${launcher[@]}" >/dev/null
cmake --build build -j"$jobs"
step "build (Release)"
run_shards build shard ""
step "tests (Release, PoCL)"

# The kernel tests of both shapes and the technique renders again on Mesa
# rusticl, the second OpenCL implementation (scripts/rusticl.sh runs it all).
if [[ "${RUSTICL:-1}" != 0 ]]; then
  scripts/rusticl.sh --ci | tee build/rusticl-ci.log
  read -r p f < <(sed -n 's/^rusticl: \([0-9]*\) passed, \([0-9]*\) failed$/\1 \2/p' build/rusticl-ci.log)  || true
  SHARDS_PASSED=$((SHARDS_PASSED + ${p:-0}))
  SHARDS_FAILED=$((SHARDS_FAILED + ${f:-0}))
  step "tests (Release, rusticl selection)"
fi

# The kernel tests of both shapes under the Oclgrind device simulator (races,
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
  # -O1 and line tables rather than RelWithDebInfo's -O2 -g: half the compile
  # time (measured per file: 17.4 vs 8.3 CPU-s for gl/FrameRenderer.cpp), and a
  # report still names file:line. Clang (installed for the fuzzers) when there:
  # it compiles the sanitized build in about 0.7x GCC's time (33 vs 47 CPU-s on
  # three heavy files; in CI the whole build 613 s against 1,052 s on two cores), and
  # the product and tests then build warning-free with both compilers.
  asan_cxx=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG")
  command -v clang++ >/dev/null &&
    asan_cxx=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG")
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "${asan_cxx[@]}" \
        -DMANYLIGHTS_SANITIZE=ON -DMANYLIGHTS_WERROR=ON -DMANYLIGHTS_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
  cmake --build build-asan -j"$jobs" --target manylights manylights-tests
  step "build (ASan + UBSan)"
  # Leak checking is off: the OpenCL ICD loader, PoCL and Mesa keep process-lifetime
  # allocations that LeakSanitizer reports; memory errors and UB still abort.
  run_shards build-asan shard "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1"
  step "tests (ASan + UBSan)"
fi
echo "== total: $(($(date +%s) - start))s =="
# Every gtest run above (PoCL, rusticl, sanitizers) in one closing line.
echo "tests: $SHARDS_PASSED passed, $SHARDS_FAILED failed"
