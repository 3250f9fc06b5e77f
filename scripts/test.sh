#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite on this machine's
# OpenCL device (PoCL on CPU-only machines) and headless GL (Mesa llvmpipe),
# then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
#   scripts/test.sh            everything
#   scripts/test.sh --no-asan  skip the sanitizer pass
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="$(nproc)"

scripts/setup.sh --no-build
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMANYLIGHTS_WERROR=ON >/dev/null
SECONDS=0
cmake --build build -j"$jobs"
echo "== build: ${SECONDS}s; tests (Release) =="
SECONDS=0
ctest --test-dir build --output-on-failure -j"$jobs"

echo "== Release tests: ${SECONDS}s =="

# The GPU-shape kernel tests under Oclgrind (scripts/oclgrind.sh) are not a
# step yet: their first full run took more than 4 minutes on this machine.

if [[ "${1:-}" != "--no-asan" ]]; then
  SECONDS=0
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMANYLIGHTS_SANITIZE=ON -DMANYLIGHTS_WERROR=ON \
        -DMANYLIGHTS_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan -j"$jobs" --target manylights manylights-tests
  echo "== tests (ASan + UBSan) =="
  # Leak checking is off: the OpenCL ICD loader, PoCL and Mesa keep process-lifetime
  # allocations that LeakSanitizer reports; memory errors and UB still abort.
  # One process for the whole suite: 1,800 sanitized process start-ups (each
  # creating a CL context and a GL context) would cost more than the tests.
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    build-asan/tests/manylights-tests --gtest_brief=1
  echo "== ASan build + tests: ${SECONDS}s =="
fi
