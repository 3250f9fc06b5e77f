#include "host/compute/Reduce.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

namespace {

template <class T>
constexpr int kindOf() {
  if constexpr (std::same_as<T, std::uint32_t>) return 0;
  if constexpr (std::same_as<T, std::int32_t>) return 1;
  return 2;
}

}  // namespace

Reducer::Reducer(ClRuntime& rt, const Options& options) : Reducer(ComputeEnv(rt), options) {}

Reducer::Reducer(const ComputeEnv& env, const Options& options) : env_(env), tuning_(resolveTuning(env, options)) {
  dummy_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, 16);
}

Reducer::Kernels& Reducer::kernels(int kind) {
  Kernels& k = kernels_[kind];
  if (!k.seg()) {
    const FittedProgram fitted = buildFitted(
        env_, tuning_, "compute/reduce.cl", "reduce", [&](std::size_t) -> Defines { return {{"ELEM_KIND", std::to_string(kind)}}; });
    const cl::Program& p = fitted.program;
    k.wg = fitted.wg;
    const char* ops[3] = {"min", "max", "sum"};
    for (int i = 0; i < 3; ++i) {
      k.chunks[i] = cl::Kernel(p, (std::string("reduce_chunks_") + ops[i]).c_str());
      k.final[i] = cl::Kernel(p, (std::string("reduce_final_") + ops[i]).c_str());
    }
    k.seg = cl::Kernel(p, "seg_minmax");
    k.tile = cl::Kernel(p, "tile_minmax");
  }
  return k;
}

void Reducer::reduceImpl(int kind, cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op,
                         cl::Buffer& out, std::size_t out_index, ClPassTimer* timer) {
  detail::checkCount(n, "Reducer::reduce");
  detail::checkBuffer(in, n * 4, "Reducer::reduce input");
  detail::checkBuffer(out, (out_index + 1) * 4, "Reducer::reduce output");
  Kernels& k = kernels(kind);
  const int o = static_cast<int>(op);
  std::size_t groups, chunk, local;
  if (tuning_.gpu()) {
    const std::size_t tile = k.wg * tuning_.items;
    // Enough groups to fill the device, few enough for one group to finish.
    groups = std::min<std::size_t>(ceilDiv(n, tile), std::max<cl_uint>(env_.info().compute_units, 1) * 8);
    if (tuning_.max_chunk) groups = std::max(groups, ceilDiv(n, tuning_.max_chunk));
    chunk = groups ? ceilDiv(n, groups) : 0;
    local = k.wg;
  } else {
    chunk = tuning_.cpuChunk(n);
    groups = n ? ceilDiv(n, chunk) : 0;
    local = 1;
  }
  cl::Buffer partials = partials_.ensure(env_, std::max<std::size_t>(groups, 1) * 4);
  detail::setArgs(k.chunks[o], in, u32(n), u32(chunk), partials);
  detail::launch(q, k.chunks[o], groups * local, local, timer, "reduce.chunks");
  detail::setArgs(k.final[o], partials, u32(groups), out, u32(out_index));
  detail::launch(q, k.final[o], local, local, timer, "reduce.final");
}

template <ReduceElement T>
T Reducer::reduce(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op, ClPassTimer* timer) {
  cl::Buffer& r = result_.ensure(env_, 4);
  reduceImpl(kindOf<T>(), q, in, n, op, r, 0, timer);
  T value{};
  q.enqueueReadBuffer(r, CL_TRUE, 0, sizeof(T), &value);
  return value;
}

template <ReduceElement T>
void Reducer::reduceAsync(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, ReduceOp op, cl::Buffer& out,
                          std::size_t out_index, ClPassTimer* timer) {
  reduceImpl(kindOf<T>(), q, in, n, op, out, out_index, timer);
}

void Reducer::segmentsImpl(int kind, cl::CommandQueue& q, const cl::Buffer& in, std::size_t n,
                           const cl::Buffer* offsets, std::size_t segment_size, std::size_t num_segments,
                           cl::Buffer& out_min, cl::Buffer& out_max, ClPassTimer* timer) {
  detail::checkCount(n, "Reducer::segmentedMinMax");
  detail::checkCount(num_segments + 1, "Reducer::segmentedMinMax segments");
  detail::checkBuffer(in, n * 4, "Reducer::segmentedMinMax input");
  if (offsets) detail::checkBuffer(*offsets, (num_segments + 1) * 4, "Reducer::segmentedMinMax offsets");
  detail::checkBuffer(out_min, num_segments * 4, "Reducer::segmentedMinMax out_min");
  detail::checkBuffer(out_max, num_segments * 4, "Reducer::segmentedMinMax out_max");
  if (num_segments == 0) return;
  Kernels& k = kernels(kind);
  std::size_t global, local, per_item = 1;
  if (tuning_.gpu()) {
    local = k.wg;
    global = num_segments * local;
  } else {
    local = 1;
    per_item = ceilDiv(num_segments, std::min(num_segments, tuning_.chunks));
    global = ceilDiv(num_segments, per_item);
  }
  detail::setArgs(k.seg, in, u32(n), offsets ? *offsets : dummy_, cl_uint(offsets != nullptr), u32(segment_size),
                  u32(num_segments), u32(per_item), out_min, out_max);
  detail::launch(q, k.seg, global, local, timer, "reduce.segments");
}

template <ReduceElement T>
void Reducer::segmentedMinMax(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n, const cl::Buffer& offsets,
                              std::size_t num_segments, cl::Buffer& out_min, cl::Buffer& out_max,
                              ClPassTimer* timer) {
  segmentsImpl(kindOf<T>(), q, in, n, &offsets, 0, num_segments, out_min, out_max, timer);
}

template <ReduceElement T>
void Reducer::segmentedMinMaxFixed(cl::CommandQueue& q, const cl::Buffer& in, std::size_t n,
                                   std::size_t segment_size, cl::Buffer& out_min, cl::Buffer& out_max,
                                   ClPassTimer* timer) {
  if (segment_size == 0) throw std::invalid_argument("Reducer::segmentedMinMaxFixed: segment_size must be > 0");
  segmentsImpl(kindOf<T>(), q, in, n, nullptr, segment_size, ceilDiv(n, segment_size), out_min, out_max, timer);
}

void Reducer::tileMinMax(cl::CommandQueue& q, const cl::Buffer& image, std::size_t width, std::size_t height,
                         std::size_t tile, cl::Buffer& out_min, cl::Buffer& out_max, ClPassTimer* timer) {
  if (tile == 0) throw std::invalid_argument("Reducer::tileMinMax: tile must be > 0");
  detail::checkCount(width * height, "Reducer::tileMinMax");
  detail::checkBuffer(image, width * height * 4, "Reducer::tileMinMax image");
  const std::size_t tiles_x = ceilDiv(width, tile), tiles_y = ceilDiv(height, tile);
  detail::checkBuffer(out_min, tiles_x * tiles_y * 4, "Reducer::tileMinMax out_min");
  detail::checkBuffer(out_max, tiles_x * tiles_y * 4, "Reducer::tileMinMax out_max");
  if (tiles_x * tiles_y == 0) return;
  Kernels& k = kernels(2);
  std::size_t global, local, cols = 1;
  if (tuning_.gpu()) {
    local = k.wg;
    global = tiles_x * tiles_y * local;
  } else {
    // Whole tile rows per work-item (memory-order walks), split into column
    // blocks only when there are too few rows to keep every core busy.
    local = 1;
    const std::size_t blocks_x = std::min(tiles_x, ceilDiv(tuning_.chunks, tiles_y));
    cols = ceilDiv(tiles_x, blocks_x);
    global = tiles_y * ceilDiv(tiles_x, cols);
  }
  detail::setArgs(k.tile, image, u32(width), u32(height), u32(tile), u32(tiles_x), u32(tiles_y), u32(cols), out_min,
                  out_max);
  detail::launch(q, k.tile, global, local, timer, "reduce.tiles");
}

#define ML_INSTANTIATE(T)                                                                                          \
  template T Reducer::reduce<T>(cl::CommandQueue&, const cl::Buffer&, std::size_t, ReduceOp, ClPassTimer*);        \
  template void Reducer::reduceAsync<T>(cl::CommandQueue&, const cl::Buffer&, std::size_t, ReduceOp, cl::Buffer&, \
                                        std::size_t, ClPassTimer*);                                                \
  template void Reducer::segmentedMinMax<T>(cl::CommandQueue&, const cl::Buffer&, std::size_t, const cl::Buffer&,  \
                                            std::size_t, cl::Buffer&, cl::Buffer&, ClPassTimer*);                  \
  template void Reducer::segmentedMinMaxFixed<T>(cl::CommandQueue&, const cl::Buffer&, std::size_t, std::size_t,  \
                                                 cl::Buffer&, cl::Buffer&, ClPassTimer*);
ML_INSTANTIATE(std::uint32_t)
ML_INSTANTIATE(std::int32_t)
ML_INSTANTIATE(float)
#undef ML_INSTANTIATE

}  // namespace ml::compute
