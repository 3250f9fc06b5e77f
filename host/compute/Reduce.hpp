#pragma once
// Reductions (min, max, sum) of uint32, int32 or float, whole-array and
// per-segment min/max, including the 2D per-tile form of tiled shading.
//
//   Reducer r(rt);
//   float zmax = r.reduce<float>(q, depth, n, ReduceOp::Max);          // blocks
//   r.reduceAsync<std::uint32_t>(q, counts, n, ReduceOp::Sum, out, 3);  // -> out[3], no wait
//   r.segmentedMinMax<float>(q, values, n, offsets, segments, mins, maxs);
//   r.segmentedMinMaxFixed<float>(q, values, n, 256, mins, maxs);       // ceil(n / 256) segments
//   r.tileMinMax(q, depth, 1920, 1080, 16, mins, maxs);                // 120 x 68 tiles, row-major
//
// Empty inputs or segments give the identities: min = the type's maximum
// (+inf for float), max = its lowest (-inf), sum = 0. Integer sums wrap mod
// 2^32; float sums are combined in a different order than a serial loop (use a
// tolerance). NaNs give unspecified results. Segment offsets (num_segments + 1
// entries, non-decreasing) are clamped to n. Not thread-safe.
#include <CL/opencl.hpp>

#include <concepts>
#include <cstddef>
#include <cstdint>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"

namespace ml::compute {

enum class ReduceOp { Min, Max, Sum };

template <class T>
concept ReduceElement = std::same_as<T, std::uint32_t> || std::same_as<T, std::int32_t> || std::same_as<T, float>;

class Reducer {
 public:
  explicit Reducer(ClRuntime& rt, const Options& options = {});
  explicit Reducer(const ComputeEnv& env, const Options& options = {});

  template <ReduceElement T>
  T reduce(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op, ClPassTimer* timer = nullptr);
  template <ReduceElement T>
  void reduceAsync(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op, cl::Buffer& out,
                   std::size_t out_index = 0, ClPassTimer* timer = nullptr);

  template <ReduceElement T>
  void segmentedMinMax(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, const cl::Buffer& offsets,
                       std::size_t num_segments, cl::Buffer& out_min, cl::Buffer& out_max,
                       ClPassTimer* timer = nullptr);
  template <ReduceElement T>
  void segmentedMinMaxFixed(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, std::size_t segment_size,
                            cl::Buffer& out_min, cl::Buffer& out_max, ClPassTimer* timer = nullptr);

  // Per-tile bounds of a width x height row-major float image, tile x tile
  // pixels per tile (edge tiles partial); ceil(width / tile) * ceil(height /
  // tile) results, row-major.
  void tileMinMax(cl::CommandQueue& q, const cl::Buffer& image, std::size_t width, std::size_t height,
                  std::size_t tile, cl::Buffer& out_min, cl::Buffer& out_max, ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }
  // The work-group size the GPU-shape kernels run with (1 for the CPU shape);
  // builds the uint32 kernels on first use.
  std::size_t workGroupSize() { return kernels(0).wg; }

 private:
  struct Kernels {
    cl::Kernel chunks[3], final[3], seg, tile;
    std::size_t wg = 1;  // what the GPU-shape kernels of this element kind run with
  };
  Kernels& kernels(int kind);
  void reduceImpl(int kind, cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op, cl::Buffer& out,
                  std::size_t out_index, ClPassTimer* timer);
  void segmentsImpl(int kind, cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, const cl::Buffer* offsets,
                    std::size_t segment_size, std::size_t num_segments, cl::Buffer& out_min, cl::Buffer& out_max,
                    ClPassTimer* timer);

  ComputeEnv env_;
  Tuning tuning_;
  Kernels kernels_[3];  // by element kind: uint32, int32, float; built on first use
  cl::Buffer dummy_;
  detail::Scratch partials_, result_;
};

template <ReduceElement T>
T reduce(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op) {
  auto s = detail::sharedFor<Reducer>(q);
  return s.obj.reduce<T>(q, in, n, op);
}

}  // namespace ml::compute
