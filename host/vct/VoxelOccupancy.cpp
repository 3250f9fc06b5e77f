#include "host/vct/VoxelOccupancy.hpp"

#include <stdexcept>
#include <string>

#include "host/compute/Detail.hpp"
#include "host/shared/voxel_occupancy.h"
#include "host/shared/voxel_types.h"

namespace ml::vct {

using compute::detail::u32;

VoxelOccupancy::VoxelOccupancy(const compute::ComputeEnv& env, const compute::Options& options)
    : env_(env), tuning_(compute::resolveTuning(env, options)) {}

void VoxelOccupancy::launchWords(cl::CommandQueue& q, cl::Kernel& k, cl_uint words_arg, std::size_t words,
                                 ClPassTimer* timer) {
  std::size_t chunk = 1, global = words, local = tuning_.wg;
  if (!tuning_.gpu()) {
    // A word costs 32 voxel loads (level 0) or up to 32 * 64 bit tests: a
    // floor of 64 words per work-item still splits a 32^3 grid's level 0.
    chunk = tuning_.cpuChunk(words, 64);
    global = compute::detail::ceilDiv(words, chunk);
    local = 1;
  }
  k.setArg(words_arg, u32(words));
  k.setArg(words_arg + 1, u32(chunk));
  compute::detail::launch(q, k, global, local, timer, "vct-occupancy");
}

void VoxelOccupancy::build(cl::CommandQueue& q, unsigned edge, const cl::Buffer& accum, ClPassTimer* timer) {
  if (edge == 0 || edge > ML_VOXEL_MAX_EDGE)
    throw std::invalid_argument("VoxelOccupancy: grid edge " + std::to_string(edge) + " is not in 1.." +
                                std::to_string(ML_VOXEL_MAX_EDGE));
  const std::size_t n = std::size_t(edge) * edge * edge;
  compute::detail::checkBuffer(accum, n * sizeof(gpu::VoxelAccum), "VoxelOccupancy accumulation buffer");
  const std::size_t bytes = std::size_t(gpu::occupancy_level_offset(edge, ML_OCC_LEVELS)) * 4;
  if (bytes > capacity_) {
    buffer_ = cl::Buffer();  // release first: the old and new buffer need not coexist
    buffer_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, bytes);
    capacity_ = bytes;
  }
  if (!voxels_()) {
    cl::Program p = compute::detail::buildShaped(env_, tuning_, "vct_occupancy.cl");
    voxels_ = cl::Kernel(p, "occupancy_voxels");
    reduce_ = cl::Kernel(p, "occupancy_reduce");
  }
  compute::detail::setArgs(voxels_, accum, u32(n), buffer_);
  launchWords(q, voxels_, 3, gpu::occupancy_words(edge), timer);
  for (unsigned l = 0; l + 1 < ML_OCC_LEVELS; ++l) {
    const unsigned de = gpu::occupancy_level_edge(edge, l + 1);
    compute::detail::setArgs(reduce_, buffer_, gpu::occupancy_level_offset(edge, l), gpu::occupancy_level_edge(edge, l),
                             gpu::occupancy_level_offset(edge, l + 1), de);
    launchWords(q, reduce_, 5, gpu::occupancy_words(de), timer);
  }
  edge_ = edge;
}

}  // namespace ml::vct
