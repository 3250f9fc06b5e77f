// The cases of manylights-kernel-bench, registered with the harness
// (kernel_bench_harness.hpp) in the order they run:
//  - per size n (addSizeCases): copy bandwidth four ways, the peers of the
//    "copy bound" (copy.host_memcpy, copy.host_memcpy_par over TBB,
//    copy.cl_enqueue_copy, copy.cl_kernel_uint4); our radix sort (uint32 keys,
//    key + value pairs, uint64 keys) and bitonic sort, with the sort peers
//    boost_compute_sort.u32 (Boost.Compute on our queue and buffer),
//    std_sort.u32 and std_sort_par.u32 (std::execution::par, TBB); exclusive
//    scan, sum reduction and compaction (half the keys kept);
//  - at 1080p (add1080pCases): scan, segmented sort of 16x16-tile-sized and
//    of variable (1..511) segments, per-tile depth min/max;
//  - tile light culling at 1080p (addTileCullCases, kernel_bench_tiled.cpp):
//    our culler, with the previous culler (tile_cull_pair_atomics) and the
//    C++ culler on TBB (tile_cull_cpp_tbb) as peers, n = lights;
//  - VCT mips (addVctCases, kernel_bench_vct.cpp): isotropic and anisotropic
//    mip propagation of a voxel volume.
// Every case checks its first run against a C++ twin. bytes counts the
// minimum traffic of the operation: a sort or scan reads and writes each
// element once (8 bytes per uint32 key), a copy likewise.
#pragma once

#include <CL/opencl.hpp>
#include <cstddef>
#include <string>

#include "host/cl/ClRuntime.hpp"
#include "host/compute/BitonicSort.hpp"
#include "host/compute/Compact.hpp"
#include "host/compute/RadixSort.hpp"
#include "host/compute/Reduce.hpp"
#include "host/compute/Scan.hpp"
#include "host/compute/SegmentedSort.hpp"
#include "kernel_bench_harness.hpp"
#include "kernel_bench_inputs.hpp"

namespace ml::bench {
void boostComputeSortU32(cl_command_queue queue, cl_mem buffer, std::size_t n);
}

namespace ml::kbench {

// The device, the primitives (tuned once) and the inputs the cases share.
struct Bench {
  Bench(ClRuntime& runtime, Harness& harness, const compute::Options& tune);
  ClRuntime& rt;
  Harness& h;
  cl::CommandQueue& q;
  compute::Options tune;
  compute::RadixSorter radix;
  compute::BitonicSorter bitonic;
  compute::Scanner scanner;
  compute::Reducer reducer;
  compute::Compactor compactor;
  compute::SegmentedSorter segsort;
  cl::Kernel copy4;
  InputSlot slot;
  SizeInputs& inputs(std::size_t n);  // this size's inputs (frees another size's)
  // Passes the radix sort makes for 32-bit keys at n (the "passes" counter).
  unsigned radixPasses(std::size_t n) const;
};

void addSizeCases(Bench& b, std::size_t n);
void addSortCases(Bench& b, std::size_t n);
void add1080pCases(Bench& b);
void addTileCullCases(Bench& b, std::size_t lights);
void addVctCases(Bench& b, unsigned edge, unsigned levels);

}  // namespace ml::kbench
