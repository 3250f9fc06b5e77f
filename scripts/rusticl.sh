#!/usr/bin/env bash
# Runs the test suite on Mesa rusticl (a second, independent OpenCL: clang ->
# SPIR-V -> NIR -> llvmpipe, work-items as SIMD lanes), the implementation
# beside PoCL on which kernels that rely on an unpromised order of work-items
# fail. Installs mesa-opencl-icd when missing (as scripts/setup.sh does).
#   scripts/rusticl.sh            the whole suite (about 15 minutes on two cores)
#   scripts/rusticl.sh --ci       CI's selection: the kernel tests of both shapes
#                                 and the technique render tests
#   scripts/rusticl.sh 'Filter*'  one gtest filter
# Env: BUILD_DIR (default build; must hold a built manylights-tests), SHARDS
# (parallel processes, default nproc). Logs: <BUILD_DIR>/tests-rusticl<i>.log.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# shellcheck source=lib/shards.sh
source scripts/lib/shards.sh
build="${BUILD_DIR:-build}"

# CI's selection: every kernel checked against its C++ twin in both shapes
# (primitives, tiled, clustered, hashed lookup, voxel passes), the driver-defect
# reproducers, and the renders of every technique against the brute-force
# reference. Left to the full run: the CLI, bench, viewer, cache and GL-only
# tests (they exercise no kernel that the selection does not).
ci_filter="Compute/*:Compute*:Shapes/*:TileSizesAndModes/*:DriverDefect*:ExactLowerBound*"
ci_filter+=":ClusteredKeys*:ClusteredUnique*:ClusteredAssign*:Render*:VctMips*:VctInject*:VctCornell*"

case "${1:-}" in
  --ci) filter="$ci_filter" ;;
  -h | --help) sed -n '2,11p' "$0"; exit 0 ;;
  "") filter="*" ;;
  -*) echo "rusticl.sh: error: unknown option '$1' (see --help)" >&2; exit 2 ;;
  *) filter="$1" ;;
esac

if ! dpkg-query -W -f='${Status}' mesa-opencl-icd 2>/dev/null | grep -q "install ok installed"; then
  scripts/setup.sh --no-build
fi
[[ -x "$build/tests/manylights-tests" ]] ||
  { echo "rusticl.sh: $build/tests/manylights-tests not built (scripts/setup.sh)" >&2; exit 2; }
export RUSTICL_ENABLE=llvmpipe
devices="$("$build/manylights" devices 2>&1 || true)"
if [[ "${devices,,}" != *rusticl* ]]; then
  echo "rusticl.sh: no rusticl device with RUSTICL_ENABLE=llvmpipe (apt-get install mesa-opencl-icd)" >&2
  exit 2
fi
SECONDS=0
status=0
run_shards "$build" rusticl "RUSTICL_ENABLE=llvmpipe MANYLIGHTS_DEVICE=rusticl" "$filter" || status=1
echo "rusticl: ${SECONDS}s, $([[ $status == 0 ]] && echo passed || echo FAILED)"
echo "rusticl: $SHARDS_PASSED passed, $SHARDS_FAILED failed"
exit "$status"
