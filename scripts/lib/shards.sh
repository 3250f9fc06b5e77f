# shellcheck shell=bash
# Sourced by scripts/test.sh and scripts/rusticl.sh: runs the test binary as one
# gtest process per core (gtest sharding), not one process per test as ctest
# does: each process loads ~270 shared libraries and opens its own CL and GL
# contexts and kernel cache, which cost more than most tests. A shard that
# fails names its log and its failed tests; every shard's summary is printed.
#   run_shards BUILD_DIR LOG_TAG ENV_ASSIGNMENTS [GTEST_FILTER]
# Logs: <BUILD_DIR>/tests-<LOG_TAG><i>.log. Returns non-zero if any shard failed;
# adds the shards' counts to SHARDS_PASSED and SHARDS_FAILED.
# Totals over every run_shards call of the process, for a closing line.
SHARDS_PASSED=0
SHARDS_FAILED=0
# count_of PASSED|FAILED LOG: the count gtest's summary line gives (0 if none).
count_of() {
  local n
  n=$(sed -n "s/^\[  $1  \] \([0-9]*\) tests\?[,.].*/\1/p" "$2" | tail -1)
  echo "${n:-0}"
}
run_shards() {
  local dir="$1" tag="$2" envs="$3" filter="${4:-*}" jobs pids=() failed=0 i log
  jobs="${SHARDS:-$(nproc)}"
  for ((i = 0; i < jobs; ++i)); do
    log="$dir/tests-$tag$i.log"
    env $envs GTEST_TOTAL_SHARDS="$jobs" GTEST_SHARD_INDEX="$i" \
      timeout 1800 "$dir/tests/manylights-tests" --gtest_brief=1 --gtest_filter="$filter" >"$log" 2>&1 &
    pids+=($!)
  done
  for ((i = 0; i < jobs; ++i)); do
    log="$dir/tests-$tag$i.log"
    if ! wait "${pids[$i]}"; then
      echo "== shard $i failed ($log) ==" >&2
      grep -E '^\[  FAILED  \]' "$log" >&2 || tail -60 "$log" >&2
      failed=1
    fi
    grep -E '^\[  (PASSED|SKIPPED|FAILED)  \] [0-9]+ test' "$log" | sed "s/^/$tag $i: /" || true
    SHARDS_PASSED=$((SHARDS_PASSED + $(count_of PASSED "$log")))
    SHARDS_FAILED=$((SHARDS_FAILED + $(count_of FAILED "$log")))
  done
  ((failed == 0))
}
