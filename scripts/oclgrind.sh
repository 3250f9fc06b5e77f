#!/usr/bin/env bash
# Runs the kernel tests in the GPU shape under Oclgrind (an OpenCL device
# simulator that checks every work-item) with data-race, uninitialized-value,
# API and out-of-bounds checking, at small sizes (MANYLIGHTS_TEST_SMALL=1).
# Passes only when every test passes and Oclgrind reports nothing.
#   scripts/oclgrind.sh                 the tests below, two processes in parallel
#   scripts/oclgrind.sh 'Gtest.Filter*' other tests (one gtest filter)
# Env: BUILD_DIR (default build; must hold a built manylights-tests),
#      OCLGRIND_JOBS (parallel processes, default 2), KEEP_LOGS=1 (keep logs).
#
# Oclgrind's device type has every bit set (CPU, GPU, accelerator), so
# Shape::Auto and `isCpu()` choices take the CPU paths under it: only tests
# that name the GPU shape run it (Compute/*/Gpu*). The CPU shape is not run:
# its kernels use `restrict`, and Oclgrind 21.10 cannot create kernels whose
# inlined calls carry the llvm.experimental.noalias.scope.decl that this makes.
# Tests that open a GL context must not run under it either (Oclgrind's LLVM
# and Mesa llvmpipe's in one process crash): the filter names only kernel
# tests checked against C++ twins with host-made inputs.
#
# Nothing is suppressed. Two bugs of Oclgrind 21.10's --uninitialized
# bookkeeping of global memory reported correct kernels, and are worked around
# by scripts/oclgrind_shadow_fix.c, preloaded in front of Oclgrind's runtime
# (it changes host-side buffer handling only; the file says how). Both were
# reproduced with a 40-line host program and one kernel that stores a global
# value in local memory, 64 work-items per group:
#   - create a 64-element buffer, write it by kernel, read it by kernel,
#     release; then the same with 256 elements: 192 reports (stale shadow of a
#     released buffer whose index was reused; MemCheckUninitialized has no
#     memoryDeallocated hook);
#   - write 100 elements of a 101-element buffer, fill the last one, read the
#     100 by kernel: 100 reports (a partial host store replaces the shadow).
# With the shim: 0 reports for both, and tests/compute_oclgrind_canary_test.cpp
# (run first, below) proves that races, uninitialized values and
# out-of-bounds accesses are still reported in this exact setup.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${BUILD_DIR:-build}"
tests="$build/tests/manylights-tests"
jobs="${OCLGRIND_JOBS:-2}"

# The primitives' GPU-shape tests and the tiled / clustered kernel tests.
filter="${1:-Compute/*Gpu*}"

command -v oclgrind >/dev/null || { echo "oclgrind.sh: oclgrind is not installed (apt-get install oclgrind)" >&2; exit 2; }
[[ -x "$tests" ]] || { echo "oclgrind.sh: $tests not built" >&2; exit 2; }

work="$(mktemp -d)"
[[ "${KEEP_LOGS:-0}" == 1 ]] && echo "oclgrind.sh: logs in $work" || trap 'rm -rf "$work"' EXIT
cc -shared -fPIC -O1 -Wall -Wextra -Werror -o "$work/shadow_fix.so" scripts/oclgrind_shadow_fix.c -ldl -lpthread
# The runtime the launcher preloads; the shim must come first to intercept it.
rt="$(oclgrind sh -c 'printf %s "${LD_PRELOAD%%:*}"')"

export MANYLIGHTS_TEST_SMALL=1
# Programs compiled under Oclgrind are cached apart from the normal cache.
export MANYLIGHTS_CACHE_DIR="${MANYLIGHTS_CACHE_DIR:-$root/$build/kernel-cache-oclgrind}"

# run NAME FILTER [gtest args...]: one process under Oclgrind; Oclgrind's
# reports go to $work/NAME.log, the test output to $work/NAME.out.
run() {
  local name="$1" filt="$2"
  shift 2
  oclgrind --data-races --uninitialized --check-api --num-threads 1 --log "$work/$name.log" \
    env LD_PRELOAD="$work/shadow_fix.so:$rt" "$tests" --gtest_filter="$filt" --gtest_brief=1 "$@" \
    >"$work/$name.out" 2>&1
}

# Reports in a log: Oclgrind separates messages with blank lines.
reports() { [[ -s "$1" ]] && awk 'BEGIN { RS = "" } END { print NR }' "$1" || echo 0; }

SECONDS=0
# 1. The canaries: each seeded bug must be reported, the two workaround cases not.
canary_ok=1
if ! MANYLIGHTS_OCLGRIND_CANARY=1 run canary "ComputeOclgrindCanary.*"; then
  echo "oclgrind.sh: canary tests failed:" >&2; cat "$work/canary.out" >&2; canary_ok=0
fi
for kernel in canary_local_race canary_uninitialized_read canary_out_of_bounds; do
  if ! grep -q "Kernel: $kernel\b" "$work/canary.log" 2>/dev/null; then
    echo "oclgrind.sh: Oclgrind did not report the seeded bug in $kernel" >&2; canary_ok=0
  fi
done
if grep -q "Kernel: canary_clean" "$work/canary.log" 2>/dev/null; then
  echo "oclgrind.sh: Oclgrind reported a correct kernel (canary_clean*): the shadow fix does not work" >&2
  awk 'BEGIN { RS = ""; ORS = "\n\n" } /canary_clean/' "$work/canary.log" | head -40 >&2; canary_ok=0
fi

# 2. The kernel tests, split over $jobs processes by gtest sharding.
pids=()
for ((i = 0; i < jobs; ++i)); do
  GTEST_TOTAL_SHARDS="$jobs" GTEST_SHARD_INDEX="$i" run "shard$i" "$filter" &
  pids+=($!)
done
failed=0
for ((i = 0; i < jobs; ++i)); do
  if ! wait "${pids[$i]}"; then failed=1; fi
done

ran=0 total=0
for ((i = 0; i < jobs; ++i)); do
  n=$(sed -n 's/^\[==========\] \([0-9]*\) tests\? from .* ran\..*/\1/p' "$work/shard$i.out" | tail -1)
  ran=$((ran + ${n:-0}))
  r=$(reports "$work/shard$i.log")
  total=$((total + r))
  if ((r > 0)); then
    echo "== Oclgrind reports of shard $i (first 60 lines; messages by kind below) ==" >&2
    head -60 "$work/shard$i.log" >&2
    awk 'BEGIN { RS = "" } { split($0, l, "\n"); k = l[1]; sub(/ (at|of|to|in) .*/, "", k); c[k]++ }
         END { for (k in c) printf "  %6d  %s\n", c[k], k }' "$work/shard$i.log" >&2
  fi
  if grep -q "FAILED\|Failure" "$work/shard$i.out"; then
    echo "== failed tests of shard $i ==" >&2
    grep -B2 -A12 "Failure\|FAILED" "$work/shard$i.out" | head -80 >&2
    failed=1
  fi
done
status=ok
((failed || total || !canary_ok || ran == 0)) && status=FAILED
echo "oclgrind: $ran tests run in ${SECONDS}s, $total Oclgrind reports, canaries $([[ $canary_ok == 1 ]] && echo ok || echo FAILED): $status"
[[ $status == ok ]]
