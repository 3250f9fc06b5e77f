#include "host/compute/BitonicSort.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

BitonicSorter::BitonicSorter(ClRuntime& rt, const Options& options) : BitonicSorter(ComputeEnv(rt), options) {}

BitonicSorter::BitonicSorter(const ComputeEnv& env, const Options& options)
    : env_(env), tuning_(resolveTuning(env, options)) {
  if (tuning_.gpu()) {
    // Keys and values of a 2 * WG block in local memory.
    while (tuning_.wg > 1 && 2 * tuning_.wg * 8 > env_.info().local_mem_size) tuning_.wg /= 2;
  }
  const FittedProgram p = buildFitted(env_, tuning_, "compute/bitonic_sort.cl", "bitonic sort");
  if (tuning_.gpu()) tuning_.wg = p.wg;
  block_ = tuning_.gpu() ? 2 * tuning_.wg : tuning_.cpu_sort_chunk;
  block_sort_ = cl::Kernel(p.program, "bitonic_block_sort");
  block_merge_ = cl::Kernel(p.program, "bitonic_block_merge");
  global_stage_ = cl::Kernel(p.program, "bitonic_global_stage");
  if (!tuning_.gpu()) global_stage2_ = cl::Kernel(p.program, "bitonic_global_stage2");
  dummy_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, 64);
}

void BitonicSorter::sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                         ClPassTimer* timer) {
  detail::checkCount(n, "BitonicSorter");
  detail::checkBuffer(keys, n * 4, "BitonicSorter keys");
  if (values) {
    detail::checkBuffer(*values, n * 4, "BitonicSorter values");
    if (detail::sameBuffer(keys, *values)) throw std::invalid_argument("BitonicSorter: keys and values alias");
  }
  if (n < 2) return;
  const bool gpu = tuning_.gpu();
  const std::size_t local = gpu ? tuning_.wg : 1;
  const std::size_t blocks = ceilDiv(n, block_);
  const std::size_t np = detail::nextPow2(n);
  const std::size_t pairs = np / 2;
  const cl::Buffer& vals = values ? *values : dummy_;
  const cl_uint hv = values != nullptr;

  // Block work: one work-item (CPU) / work-group (GPU) per block.
  const std::size_t block_global = blocks * local;
  detail::setArgs(block_sort_, keys, vals, hv, u32(n), u32(block_));
  detail::launch(q, block_sort_, block_global, local, timer, "bitonic.block_sort");
  detail::setArgs(block_merge_, keys, vals, hv, u32(n), u32(block_));

  // Cross-block stages: CPU work-items take contiguous comparator ranges
  // (multiples of 8 for the 8-wide runs) and do two stages per sweep where
  // both cross blocks; GPU work-items one comparator of one stage each.
  std::size_t per_item = 1, stage_global = pairs, per_item2 = 1, stage2_global = 0;
  const std::size_t quads = np / 4;
  if (!gpu) {
    per_item = detail::roundUp(ceilDiv(pairs, tuning_.chunks), 8);
    stage_global = ceilDiv(pairs, per_item);
    per_item2 = detail::roundUp(ceilDiv(std::max<std::size_t>(quads, 1), tuning_.chunks), 8);
    stage2_global = ceilDiv(quads, per_item2);
  }
  for (std::size_t size = 2 * block_; size <= np; size <<= 1) {
    bool flip = true;
    for (std::size_t h = size / 2; h >= block_; flip = false) {
      if (!gpu && h / 2 >= block_) {
        detail::setArgs(global_stage2_, keys, vals, hv, u32(n), u32(h), cl_uint(flip), u32(per_item2), u32(quads));
        detail::launch(q, global_stage2_, stage2_global, local, timer, "bitonic.global_stage");
        h >>= 2;
      } else {
        detail::setArgs(global_stage_, keys, vals, hv, u32(n), u32(h), cl_uint(flip), u32(per_item), u32(pairs));
        detail::launch(q, global_stage_, stage_global, local, timer, "bitonic.global_stage");
        h >>= 1;
      }
    }
    detail::launch(q, block_merge_, block_global, local, timer, "bitonic.block_merge");
  }
}

void bitonic_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n) {
  auto s = detail::sharedFor<BitonicSorter>(q);
  s.obj.sort(q, keys, values, n);
}

}  // namespace ml::compute
