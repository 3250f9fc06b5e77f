#pragma once
// Bitonic sort of uint32 keys, optionally with a uint32 payload, any n, in
// place. Ascending; not stable (equal keys may permute their payloads).
//
//   BitonicSorter sorter(rt);
//   sorter.sort(q, keys, &values, n);
//   bitonic_sort(q, keys, nullptr, n);   // free function, shared sorter per device
//
// O(n log^2 n) work: blocks that fit in fast memory (a work-item's cache on
// CPUs, a work-group's local memory on GPUs) are sorted and merged there; the
// merge stages that cross blocks run as one global pass each. n that is not a
// power of two is handled as if padded with maximum keys, without a padding
// buffer (see kernels/compute/prim_bitonic_network.cl). Enqueued on `q`, non-blocking; no
// scratch memory. Not thread-safe.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"

namespace ml::compute {

class BitonicSorter {
 public:
  explicit BitonicSorter(ClRuntime& rt, const Options& options = {});
  explicit BitonicSorter(const ComputeEnv& env, const Options& options = {});

  void sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }
  // Elements sorted per block in fast memory (CPU: per work-item; GPU: 2 * work-group size).
  std::size_t blockSize() const { return block_; }

 private:
  ComputeEnv env_;
  Tuning tuning_;
  std::size_t block_ = 0;
  cl::Kernel block_sort_, block_merge_, global_stage_, global_stage2_;
  cl::Buffer dummy_;
};

void bitonic_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n);

}  // namespace ml::compute
