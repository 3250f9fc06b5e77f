#!/usr/bin/env bash
# Runs the kernel tests in both shapes (GPU: work-groups cooperating through
# local memory; CPU: a work-item per chunk with private state) under Oclgrind
# (an OpenCL device simulator that checks every work-item) with data-race,
# uninitialized-value, API and out-of-bounds checking, at small sizes
# (MANYLIGHTS_TEST_SMALL=1).
# Passes only when every test passes and Oclgrind reports nothing.
#   scripts/oclgrind.sh                 the tests below, two processes in parallel
#   scripts/oclgrind.sh --ci             CI's shorter selection
#   scripts/oclgrind.sh 'Gtest.Filter*' other tests (one gtest filter, -cl-opt-disable)
# Env: BUILD_DIR (default build; must hold a built manylights-tests),
#      OCLGRIND_JOBS (parallel processes, default 2), KEEP_LOGS=1 (keep logs).
#
# Oclgrind's device type has every bit set (CPU, GPU, accelerator), so
# Shape::Auto and `isCpu()` choices take the CPU paths under it: the tests run
# are those that name their shape (Compute/*Gpu*, *_gpu, */gpu and
# Compute/*Cpu*, *_cpu, */cpu). ClusteredAssignShapes.GpuShapeEqualsCpuShapeExactly
# builds both shapes and is left out (Shapes/ClusteredAssign.*/{cpu,gpu} run
# each alone).
# Tests that open a GL context must not run under it either (Oclgrind's LLVM
# and Mesa llvmpipe's in one process crash): the filter names only kernel
# tests checked against C++ twins with host-made inputs.
#
# The tiled and clustered kernels are built with -cl-opt-disable (Oclgrind's
# --build-options): at -O2, LLVM 14 emits IR there that Oclgrind 21.10 cannot
# simulate: `freeze` (from a / b next to a % b; fatal error, removed from the
# kernels), `llvm.experimental.noalias.scope.decl` (inlined calls with
# `restrict` arguments; kernel creation fails) and shufflevector masks with
# undef lanes (horizontal sums such as sphere_inside_plane's; the
# --uninitialized plugin crashes). Unoptimized IR keeps every load and store
# of the source, so nothing the checks look at is folded away; Oclgrind's own
# clang is the compiler here, not a vendor's, either way. The primitives run
# at -O2: they simulate cleanly there and are about 4x slower unoptimized
# (bitonic Gpu_Keys: 175 s vs 44 s). The canaries run in both setups.
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
# With the shim: 0 reports for both, and tests/compute/compute_oclgrind_canary_test.cpp
# (run first, below) proves that races, uninitialized values and
# out-of-bounds accesses are still reported in this exact setup.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${BUILD_DIR:-build}"
tests="$build/tests/manylights-tests"
jobs="${OCLGRIND_JOBS:-2}"

# Groups: name, gtest filter, Oclgrind build options. The GPU-shape tests of
# the primitives (scan, reduce, compact/unique, radix, bitonic, segmented
# sort), then those of the tiled and clustered kernels. Left out for time
# (about 4 minutes in all on two cores is the budget of this CI step):
#   - Shapes/ClusteredAssign.*/gpu (the kernels/clustered/ GPU shape: seven
#     assigners over three frames; over 100 CPU-s unoptimized, unfinished);
#     scripts/oclgrind.sh 'Shapes/ClusteredAssign.*/gpu' runs it;
#   - the radix sort tests but Gpu_Pairs32 (which runs both GPU kernels,
#     radix_hist and radix_scatter, keys and values): each takes about two
#     CPU-minutes; OCLGRIND_BUILD_OPTIONS= scripts/oclgrind.sh 'Compute/Radix*Gpu*'
#     runs them all (OCLGRIND_BUILD_OPTIONS: a custom filter's build options,
#     default -cl-opt-disable);
#   - ReduceShapeTest.SegmentedMinMaxFixedSize/Gpu and
#     ClusteredUnique.EveryPixelADifferentCluster/gpu (a minute or more each
#     here; their kernels run in the other reduce and unique tests).
all_checks="--data-races --uninitialized"
# The CPU shape's build options: -Drestrict= as well, since its kernels pass
# `restrict` pointers (for PoCL's vectorizer) into inlined helpers, whose
# llvm.experimental.noalias.scope.decl Oclgrind 21.10 cannot create a kernel
# from even unoptimized; dropping the qualifier (a promise of no aliasing)
# changes no result of a correct kernel.
cpu_opts="-cl-opt-disable -Drestrict="
# The CPU shape (a work-item per chunk, private state) runs with the same
# checks, but three kernel families only with --data-races: Oclgrind 21.10's
# --uninitialized plugin crashes the process (segfault, no report) on the
# 8-wide vector swizzles of the CPU sorting networks (compute/prim_bitonic_network.cl:
# bitonic and segmented sort, and cluster unique's sort methods); with
# --data-races they report nothing. Left out for time (over 150 s each under
# the simulator): ComputeRadixSort.CpuWideDigitsAndBalancedPasses,
# Shapes/ClusteredAssign.*/cpu, Compute/RadixSortTest.*/Cpu_Pairs64 and
# Shapes/VctOccupancy.*/cpu (112 s with --data-races alone, 0 reports).
if [[ "${1:-}" == --ci ]]; then
  # CI's selection (about 4 minutes on two idle cores): each GPU-shape kernel at
  # least once, one test per primitive family; the rest of the default set runs
  # without --ci. The voxel-shadow injection, distance-volume and march tests
  # add about a minute.
  prims="Compute/BitonicSortTest.MatchesStdSort/Gpu_Pairs:Compute/CompactTest.ValuesAndIndicesMatchCopyIf/Gpu_Half"
  prims+=":Compute/UniqueTest.MatchesStdUnique/Gpu_Random:Compute/ReduceTest.MinMaxSumMatchStd/Gpu_F32"
  prims+=":Compute/ReduceShapeTest.SegmentedMinMaxWithOffsets/Gpu:Compute/ReduceShapeTest.TileMinMaxOfDepthImage/Gpu"
  prims+=":Compute/ScanTest.MatchesStdScan/Gpu_Exclusive:Compute/ScanTest.InPlace/Gpu_Inclusive"
  prims+=":Compute/SegmentedSortShapeTest.OffsetSegmentsWithAStatedBound/Gpu:Compute/RadixSortTest.MatchesStableSort/Gpu_Pairs32"
  # The CPU shape: one test per primitive family (the vector sorting networks
  # with races checked only, see above) and the technique kernels' chunked forms.
  cpu_prims="Compute/CompactTest.ValuesAndIndicesMatchCopyIf/Cpu_Half:Compute/UniqueTest.MatchesStdUnique/Cpu_Random"
  cpu_prims+=":Compute/ReduceTest.MinMaxSumMatchStd/Cpu_F32:Compute/ReduceShapeTest.SegmentedMinMaxWithOffsets/Cpu"
  cpu_prims+=":Compute/ReduceShapeTest.TileMinMaxOfDepthImage/Cpu:Compute/ScanTest.MatchesStdScan/Cpu_Exclusive"
  cpu_prims+=":Compute/ScanTest.InPlace/Cpu_Inclusive:Compute/RadixShapeTest.DigitWidthsAndOddPassCounts/Cpu"
  cpu_networks="Compute/BitonicSortTest.MatchesStdSort/Cpu_Pairs:Compute/SegmentedSortShapeTest.OffsetSegmentsWithAStatedBound/Cpu"
  cpu_networks+=":Shapes/ClusteredUnique.AllPixelsOneCluster/cpu"
  cpu_techniques="TileSizesAndModes/TiledCulling.*minmax_16_cpu:TileSizesAndModes/TiledCulling.*mask_8_cpu"
  cpu_techniques+=":Shapes/TiledChunked.RectanglesWiderThanTheColumnCache/cpu:Shapes/TiledChunked.DuplicatesAndExtremes/cpu"
  cpu_techniques+=":Shapes/TiledCullingEdges.*/cpu:Shapes/ClusteredKeys.*/cpu:Shapes/VctInject.VoxelShadows*/cpu"
  cpu_techniques+=":Shapes/VctInject.ClosedWall*/cpu:Shapes/VctMips.FiltersKnownValues/cpu:Shapes/VctShadowMarch.SkipsEmptySpace/cpu"
  groups=("primitives|$prims|"
          "techniques|TileSizesAndModes/TiledCulling.*_gpu:Shapes/TiledCullingEdges.*/gpu:Shapes/ClusteredKeys.*/gpu:Shapes/ClusteredUnique.AllPixelsOneCluster/gpu:Shapes/VctInject.VoxelShadows*/gpu:Shapes/VctInject.ClosedWall*/gpu:Shapes/VctOccupancy.*/gpu:Shapes/VctShadowMarch.*/gpu|-cl-opt-disable"
          "primitives_cpu|$cpu_prims|$cpu_opts"
          "networks_cpu|$cpu_networks|$cpu_opts|--data-races"
          "techniques_cpu|$cpu_techniques|$cpu_opts")
elif (($#)); then
  groups=("custom|$1|${OCLGRIND_BUILD_OPTIONS--cl-opt-disable}|${OCLGRIND_CHECKS:-$all_checks}")
else
  radix_left_out="Compute/RadixSortTest.MatchesStableSort/Gpu_Keys*:Compute/RadixSortTest.MatchesStableSort/Gpu_Pairs32Bits13"
  radix_left_out+=":Compute/RadixSortTest.MatchesStableSort/Gpu_Pairs64:Compute/RadixShapeTest.*"
  cpu_radix_left_out="Compute/RadixSortTest.MatchesStableSort/Cpu_Pairs64"
  cpu_network_tests="Compute/BitonicSortTest.*Cpu*:Compute/SegmentedSort*Cpu*"
  groups=("primitives|Compute/*Gpu*-$radix_left_out:Compute/ReduceShapeTest.SegmentedMinMaxFixedSize/Gpu|"
          "techniques|TileSizesAndModes/TiledCulling.*_gpu:Shapes/TiledCullingEdges.*/gpu:Shapes/ClusteredKeys.*/gpu:Shapes/ClusteredUnique.*/gpu:Shapes/VctMips.*/gpu:Shapes/VctInject.*/gpu:Shapes/VctOccupancy.*/gpu:Shapes/VctShadowMarch.*/gpu-Shapes/ClusteredUnique.EveryPixelADifferentCluster/gpu|-cl-opt-disable"
          "primitives_cpu|Compute/*Cpu*-$cpu_radix_left_out:$cpu_network_tests|$cpu_opts"
          "networks_cpu|$cpu_network_tests:Shapes/ClusteredUnique.*/cpu-Shapes/ClusteredUnique.EveryPixelADifferentCluster/cpu|$cpu_opts|--data-races"
          "techniques_cpu|TileSizesAndModes/TiledCulling.*_cpu:Shapes/TiledChunked.*/cpu:Shapes/TiledCullingEdges.*/cpu:Shapes/ClusteredKeys.*/cpu:Shapes/ClusteredUnique.EveryPixelADifferentCluster/cpu:Shapes/VctMips.*/cpu:Shapes/VctInject.*/cpu:Shapes/VctShadowMarch.*/cpu|$cpu_opts")
fi

command -v oclgrind >/dev/null || { echo "oclgrind.sh: oclgrind is not installed (apt-get install oclgrind)" >&2; exit 2; }
[[ -x "$tests" ]] || { echo "oclgrind.sh: $tests not built" >&2; exit 2; }

work="$(mktemp -d)"
[[ "${KEEP_LOGS:-0}" == 1 ]] && echo "oclgrind.sh: logs in $work" || trap 'rm -rf "$work"' EXIT
cc -shared -fPIC -O1 -Wall -Wextra -Werror -o "$work/shadow_fix.so" scripts/oclgrind_shadow_fix.c -ldl -lpthread
# The runtime the launcher preloads; the shim must come first to intercept it.
rt="$(oclgrind sh -c 'printf %s "${LD_PRELOAD%%:*}"')"

export MANYLIGHTS_TEST_SMALL=1
# Programs compiled under Oclgrind are cached apart from the normal cache, one
# folder per build options (those Oclgrind adds are not part of the cache key).
[[ "$build" == /* ]] && build_abs="$build" || build_abs="$root/$build"
cache_root="${MANYLIGHTS_CACHE_DIR:-$build_abs}"


# run NAME FILTER OPTIONS CHECKS [gtest args...]: one process under Oclgrind,
# programs built with OPTIONS added, Oclgrind's CHECKS (--check-api and
# out-of-bounds checks are always on); Oclgrind's reports go to $work/NAME.log,
# the test output to $work/NAME.out.
run() {
  local name="$1" filt="$2" opts="$3" checks="$4"
  shift 4
  MANYLIGHTS_CACHE_DIR="$cache_root/kernel-cache-oclgrind${opts// /}" \
    oclgrind ${opts:+--build-options "$opts"} $checks --check-api --num-threads 1 \
    --log "$work/$name.log" \
    env LD_PRELOAD="$work/shadow_fix.so:$rt" "$tests" --gtest_filter="$filt" --gtest_brief=1 "$@" \
    >"$work/$name.out" 2>&1
}

# Reports in a log: Oclgrind separates messages with blank lines.
reports() { [[ -s "$1" ]] && awk 'BEGIN { RS = "" } END { print NR }' "$1" || echo 0; }

SECONDS=0
setups=()
for g in "${groups[@]}"; do
  IFS='|' read -r _ _ gopts _ <<<"$g"
  [[ " ${setups[*]/#/|} " == *" |$gopts "* ]] || setups+=("$gopts")
done
# Every run at once (canaries of each build setup, every group's shards):
# each Oclgrind process is single-threaded, and starting them together keeps
# both cores busy to the end instead of waiting for each group's slowest shard.
pids=() shards=() failed=0 c=0
for opts in "${setups[@]}"; do
  c=$((c + 1))
  MANYLIGHTS_OCLGRIND_CANARY=1 run "canary$c" "ComputeOclgrindCanary.*" "$opts" "$all_checks" &
  pids+=($!)
done
ncanary=${#pids[@]}
for g in "${groups[@]}"; do
  IFS='|' read -r gname gfilter gopts gchecks <<<"$g"
  for ((i = 0; i < jobs; ++i)); do
    GTEST_TOTAL_SHARDS="$jobs" GTEST_SHARD_INDEX="$i" run "$gname$i" "$gfilter" "$gopts" "${gchecks:-$all_checks}" &
    pids+=($!)
    shards+=("$gname$i")
  done
done
canary_ok=1
for ((k = 0; k < ${#pids[@]}; ++k)); do
  if ! wait "${pids[$k]}"; then
    if ((k < ncanary)); then
      echo "oclgrind.sh: canary tests failed:" >&2; cat "$work/canary$((k + 1)).out" >&2; canary_ok=0
    else
      failed=1
    fi
  fi
done
echo "oclgrind: all runs done at ${SECONDS}s"

# The canaries, in each build setup: each seeded bug must be reported, the
# two workaround cases not.
c=0
for opts in "${setups[@]}"; do
  c=$((c + 1))
  for kernel in canary_local_race canary_uninitialized_read canary_out_of_bounds; do
    if ! grep -q "Kernel: $kernel\b" "$work/canary$c.log" 2>/dev/null; then
      echo "oclgrind.sh: Oclgrind did not report the seeded bug in $kernel (build options '$opts')" >&2; canary_ok=0
    fi
  done
  if grep -q "Kernel: canary_clean" "$work/canary$c.log" 2>/dev/null; then
    echo "oclgrind.sh: Oclgrind reported a correct kernel (canary_clean*): the shadow fix does not work" >&2
    awk 'BEGIN { RS = ""; ORS = "\n\n" } /canary_clean/' "$work/canary$c.log" | head -40 >&2; canary_ok=0
  fi
done

ran=0 total=0
for sh in "${shards[@]}"; do
  n=$(sed -n 's/^\[==========\] \([0-9]*\) tests\? from .* ran\..*/\1/p' "$work/$sh.out" | tail -1)
  ran=$((ran + ${n:-0}))
  r=$(reports "$work/$sh.log")
  total=$((total + r))
  if ((r > 0)); then
    echo "== Oclgrind reports of $sh (first 60 lines; messages by kind below) ==" >&2
    head -60 "$work/$sh.log" >&2
    awk 'BEGIN { RS = "" } { split($0, l, "\n"); k = l[1]; sub(/ (at|of|to|in) .*/, "", k); c[k]++ }
         END { for (k in c) printf "  %6d  %s\n", c[k], k }' "$work/$sh.log" >&2
  fi
  if grep -q "FAILED\|Failure" "$work/$sh.out"; then
    echo "== failed tests of $sh ==" >&2
    grep -B2 -A12 "Failure\|FAILED" "$work/$sh.out" | head -80 >&2
    failed=1
  fi
done
status=ok
((failed || total || !canary_ok || ran == 0)) && status=FAILED
echo "oclgrind: $ran tests run in ${SECONDS}s, $total Oclgrind reports, canaries $([[ $canary_ok == 1 ]] && echo ok || echo FAILED): $status"
[[ $status == ok ]]
