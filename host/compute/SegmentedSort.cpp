#include "host/compute/SegmentedSort.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

SegmentedSorter::SegmentedSorter(ClRuntime& rt, const Options& options) : SegmentedSorter(ComputeEnv(rt), options) {}

SegmentedSorter::SegmentedSorter(const ComputeEnv& env, const Options& options)
    : env_(env), tuning_(resolveTuning(env, options)) {
  // Keys + values, 8 bytes per element, in at most half the local memory
  // (leaving room for the runtime's own use), and no more than 8 comparators
  // per work-item per stage.
  auto capacity = [&](std::size_t wg) {
    const std::size_t c = std::min<std::size_t>(16 * wg, detail::prevPow2(env_.info().local_mem_size / 16));
    return std::max<std::size_t>(c, 2);
  };
  const FittedProgram p =
      buildFitted(env_, tuning_, "compute/segmented_sort.cl", "segmented sort", [&](std::size_t wg) -> Defines {
        if (!tuning_.gpu()) return {};
        return {{"SEG_LOCAL", std::to_string(capacity(wg))}};
      });
  if (tuning_.gpu()) {
    tuning_.wg = p.wg;
    local_capacity_ = capacity(p.wg);
  }
  kernel_ = cl::Kernel(p.program, "segmented_sort");
  dummy_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, 64);
}

void SegmentedSorter::run(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                          const cl::Buffer* offsets, std::size_t segment_size, std::size_t num_segments,
                          ClPassTimer* timer, std::size_t max_segment) {
  detail::checkCount(n, "SegmentedSorter");
  detail::checkCount(num_segments + 1, "SegmentedSorter segments");
  detail::checkBuffer(keys, n * 4, "SegmentedSorter keys");
  if (values) {
    detail::checkBuffer(*values, n * 4, "SegmentedSorter values");
    if (detail::sameBuffer(keys, *values)) throw std::invalid_argument("SegmentedSorter: keys and values alias");
  }
  if (offsets) detail::checkBuffer(*offsets, (num_segments + 1) * 4, "SegmentedSorter offsets");
  if (num_segments == 0 || n == 0) return;
  std::size_t global, local, last_arg;
  if (tuning_.gpu()) {
    // The GPU kernel's stage loops run to a launch-wide power-of-two bound
    // (see kernels/compute/segmented_sort.cl for why): exact for fixed sizes; with
    // offsets, whose lengths the host does not know, the caller's bound or n.
    local = tuning_.wg;
    global = num_segments * local;
    const std::size_t longest = offsets ? (max_segment ? max_segment : n) : segment_size;
    last_arg = detail::nextPow2(std::max<std::size_t>(1, std::min(n, longest)));
    last_stage_bound_ = last_arg;
  } else {
    // Four runs of segments per chunk slot: segment lengths vary, and more,
    // shorter runs let PoCL's workers balance them.
    local = 1;
    last_arg = ceilDiv(num_segments, std::min(num_segments, tuning_.chunks * 4));  // segments per work-item
    global = ceilDiv(num_segments, last_arg);
  }
  detail::setArgs(kernel_, keys, values ? *values : dummy_, cl_uint(values != nullptr), u32(n),
                  offsets ? *offsets : dummy_, cl_uint(offsets != nullptr), u32(segment_size), u32(num_segments),
                  u32(last_arg));
  detail::launch(q, kernel_, global, local, timer, "segmented_sort");
}

void SegmentedSorter::sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                           const cl::Buffer& offsets, std::size_t num_segments, ClPassTimer* timer,
                           std::size_t max_segment) {
  run(q, keys, values, n, &offsets, 0, num_segments, timer, max_segment);
}

void SegmentedSorter::sortFixed(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                                std::size_t segment_size, ClPassTimer* timer) {
  if (segment_size == 0) throw std::invalid_argument("SegmentedSorter::sortFixed: segment_size must be > 0");
  run(q, keys, values, n, nullptr, segment_size, ceilDiv(n, segment_size), timer, 0);
}

void segmented_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                    const cl::Buffer& offsets, std::size_t num_segments) {
  auto s = detail::sharedFor<SegmentedSorter>(q);
  s.obj.sort(q, keys, values, n, offsets, num_segments);
}

}  // namespace ml::compute
