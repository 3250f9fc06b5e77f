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
cmake --build build -j"$jobs"
echo "== tests (Release) =="
ctest --test-dir build --output-on-failure -j"$jobs"

if [[ "${1:-}" != "--no-asan" ]]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMANYLIGHTS_SANITIZE=ON -DMANYLIGHTS_WERROR=ON \
        -DMANYLIGHTS_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan -j"$jobs" --target manylights manylights-tests
  echo "== tests (ASan + UBSan) =="
  # Leak checking is off: the OpenCL ICD loader, PoCL and Mesa keep process-lifetime
  # allocations that LeakSanitizer reports; memory errors and UB still abort.
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j"$jobs"
fi
