#pragma once
// Sorts many independent segments of uint32 keys (optionally with a uint32
// payload) in one launch, in place: e.g. the light keys of every screen tile.
//
//   SegmentedSorter s(rt);
//   s.sort(q, keys, &values, n, offsets, segments);  // segment i = [offsets[i], offsets[i + 1])
//   s.sortFixed(q, keys, nullptr, n, 256);           // segments of 256 (the last may be shorter)
//   segmented_sort(q, keys, &values, n, offsets, segments);
//
// Ascending within each segment, not stable; elements outside every segment
// are untouched. `offsets` has segments + 1 non-decreasing entries; they are
// clamped to n, so bad offsets cannot write out of bounds. A bitonic network
// per segment: CPU devices give each work-item a run of segments, GPUs a
// work-group per segment (local memory up to a device-derived size, global
// memory beyond, so any segment length works). Built for many small segments;
// one huge segment is better served by RadixSorter / BitonicSorter. On the GPU
// shape every work-group steps through the stages of the longest possible
// segment (next_pow2(segment_size), or next_pow2(n) with offsets), skipping
// those beyond its own; see kernels/segmented_sort.cl.
// Enqueued on `q`, non-blocking. Not thread-safe.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"

namespace ml::compute {

class SegmentedSorter {
 public:
  explicit SegmentedSorter(ClRuntime& rt, const Options& options = {});
  explicit SegmentedSorter(const ComputeEnv& env, const Options& options = {});

  void sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, const cl::Buffer& offsets,
            std::size_t num_segments, ClPassTimer* timer = nullptr);
  void sortFixed(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, std::size_t segment_size,
                 ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }
  // GPU shape: longest segment sorted in local memory (longer ones run in global memory).
  std::size_t localCapacity() const { return local_capacity_; }

 private:
  void run(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, const cl::Buffer* offsets,
           std::size_t segment_size, std::size_t num_segments, ClPassTimer* timer);

  ComputeEnv env_;
  Tuning tuning_;
  std::size_t local_capacity_ = 0;
  cl::Kernel kernel_;
  cl::Buffer dummy_;
};

void segmented_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                    const cl::Buffer& offsets, std::size_t num_segments);

}  // namespace ml::compute
