#pragma once
// Sorts many independent segments of uint32 keys (optionally with a uint32
// payload) in one launch, in place: e.g. the light keys of every screen tile.
//
//   SegmentedSorter s(rt);
//   s.sort(q, keys, &values, n, offsets, segments);  // segment i = [offsets[i], offsets[i + 1])
//   s.sort(q, keys, &values, n, offsets, segments, nullptr, 1024);  // ... no segment longer than 1024
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
// segment, skipping those beyond its own (see kernels/compute/segmented_sort.cl): that
// bound is next_pow2(segment_size) for fixed sizes and, with offsets,
// next_pow2(max_segment) when the caller states one (e.g. the pixels of a
// screen tile: 55 barrier steps for 32x32 instead of 231 for next_pow2(n) at
// 1080p), else next_pow2(n). A segment longer than a stated max_segment is a
// caller bug: no write leaves its segment, but it is then not fully sorted on
// the GPU shape.
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

  // max_segment: an upper bound on every segment's length, 0 = unknown (n).
  void sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, const cl::Buffer& offsets,
            std::size_t num_segments, ClPassTimer* timer = nullptr, std::size_t max_segment = 0);
  void sortFixed(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, std::size_t segment_size,
                 ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }
  // GPU shape: longest segment sorted in local memory (longer ones run in global memory).
  std::size_t localCapacity() const { return local_capacity_; }
  // GPU shape: the power-of-two stage bound of the last launch (0 before any, or on the CPU shape).
  std::size_t lastStageBound() const { return last_stage_bound_; }

 private:
  void run(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, const cl::Buffer* offsets,
           std::size_t segment_size, std::size_t num_segments, ClPassTimer* timer, std::size_t max_segment);

  ComputeEnv env_;
  Tuning tuning_;
  std::size_t local_capacity_ = 0;
  std::size_t last_stage_bound_ = 0;
  cl::Kernel kernel_;
  cl::Buffer dummy_;
};

void segmented_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                    const cl::Buffer& offsets, std::size_t num_segments);

}  // namespace ml::compute
