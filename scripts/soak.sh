#!/usr/bin/env bash
# Runs the randomized tests (those drawing MANYLIGHTS_TEST_SEED / test::freshSeed)
# many times, each round a fresh process with fresh seeds, and prints every
# failing test with the seed that replays it:
#   MANYLIGHTS_TEST_SEED=<seed> build/tests/manylights-tests --gtest_filter=<test>
# Usage: scripts/soak.sh [ROUNDS] [FILTER]    ROUNDS default 50
#   FILTER: a gtest filter, or "hashed" / "rest" / "all" (default) for the
#   randomized tests of hashed shading, of everything else, or both.
# Exit 1 if any round failed. Env: TEST_BIN (default build/tests/manylights-tests).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

# Tests that take seeds from test::freshSeed (grep tests/ for freshSeed when adding one).
hashed="HashedDynamic.*:HashedKeys.OwnRangesKeepCountAndCapacityThroughResizeAndCompaction:HashedMask.*:HashedMaskGeometry.*"
hashed+=":HashedOctree.*:HashedThreads.*:HashedPsh.*:HashedRender.AnimatedLightsMatchAFreshBuild"
rest="*/ClusteredAssign.BruteMatchesReferenceAndBvhMatchesBrute/*:*/ClusteredKeys.KernelMatchesReference/*"
rest+=":*/ClusteredUnique.*:*BitonicSort*:*CompactTest.*:*UniqueTest.*:ComputeCompact.*:*RadixSort*:*ReduceTest.*"
rest+=":*ReduceShapeTest.*:*ScanTest.*:ComputeScan.*:*SegmentedSort*:*SharedBufferTest.RoundTripGlClGl*"
rest+=":GBufferNormal.*:CameraMatrices.*:CameraJson.RoundTripSingleAndPath:LightGenerate.*"
rest+=":LightJson.RoundTripIsBitExact:*TiledCulling.*:*/TiledCullingEdges.*"

rounds="${1:-50}"
case "${2:-all}" in
  all) filter="$hashed:$rest" ;;
  hashed) filter="$hashed" ;;
  rest) filter="$rest" ;;
  *) filter="$2" ;;
esac
if ! [[ "$rounds" =~ ^[1-9][0-9]*$ ]]; then
  echo "soak.sh: ROUNDS must be a positive integer (got '$rounds')" >&2
  exit 2
fi
bin="${TEST_BIN:-build/tests/manylights-tests}"
[[ -x "$bin" ]] || { echo "soak.sh: $bin not built (cmake --build build --target manylights-tests)" >&2; exit 2; }
unset MANYLIGHTS_TEST_SEED  # fresh seeds every round
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# A private copy: a rebuild during the soak must not make rounds fail.
cp "$bin" "$work/manylights-tests"
bin="$work/manylights-tests"

# Prints "test seed(s)" for every failed test case of a gtest XML report.
failures() {
  python3 - "$1" <<'PY'
import sys, xml.etree.ElementTree as ET
for case in ET.parse(sys.argv[1]).iter("testcase"):
    if case.find("failure") is None:
        continue
    seeds = [p.get("value") for p in case.iter("property") if p.get("name") == "seed"]
    seeds += [v for k, v in case.attrib.items() if k == "seed"]
    print(f"{case.get('classname')}.{case.get('name')} seed {','.join(seeds) or 'none'}")
PY
}

failed_rounds=0 failed_tests=0 tests_run=0
declare -A distinct=()
SECONDS=0
for ((r = 1; r <= rounds; ++r)); do
  xml="$work/round.xml" log="$work/round.log"
  rm -f "$xml"
  rc=0
  "$bin" --gtest_filter="$filter" --gtest_output="xml:$xml" --gtest_brief=1 >"$log" 2>&1 || rc=$?
  if [[ -s "$xml" ]]; then
    tests_run=$((tests_run + $(grep -c '<testcase ' "$xml" || true)))
    mapfile -t lines < <(failures "$xml")
  else
    lines=("(crash: no report, exit $rc) seed unknown")
    tail -5 "$log" | sed 's/^/    /'
  fi
  ((rc == 0 || ${#lines[@]})) || lines=("(exit $rc without a failed test) seed unknown")
  if ((${#lines[@]})); then
    failed_rounds=$((failed_rounds + 1))
    for l in "${lines[@]}"; do
      echo "soak: round $r FAILED: $l"
      failed_tests=$((failed_tests + 1))
      distinct["${l%% *}"]=1
    done
  fi
  echo "soak: round $r/$rounds done (${SECONDS}s, $failed_rounds failed round(s))"
done
echo "soak: $rounds rounds, $tests_run test runs, $failed_tests failure(s) in $failed_rounds round(s)," \
     "${#distinct[@]} distinct test(s), ${SECONDS}s; filter: $filter"
((failed_rounds == 0))
