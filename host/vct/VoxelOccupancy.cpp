#include "host/vct/VoxelOccupancy.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "host/cl/Launch.hpp"
#include "host/compute/FittedProgram.hpp"
#include "host/shared/voxel_occupancy.h"
#include "host/shared/voxel_types.h"

namespace ml::vct {


VoxelOccupancy::VoxelOccupancy(const compute::ComputeEnv& env, const compute::Options& options)
    : env_(env), tuning_(compute::resolveTuning(env, options)) {}

namespace {

// Loop iterations one work-item may take where the device ends a work-item's
// loops after 65,535 in total (llvmpipe; Tuning::max_chunk is set there,
// tests/driver/driver_loop_cap_test.cpp): below the cap, with room for rounding.
constexpr std::size_t kLoopCapMargin = 60000;

// The most lines per work-item under that cap (0 where the device has none):
// a line of distance_lines costs at most edge * (ML_OCC_MAX_DISTANCE + 1) + 1
// iterations (the outward search stops below the clamp), one of
// distance_rows 2 * edge + 1.

std::size_t linesWithinLoopCap(const compute::Tuning& t, unsigned edge) {
  if (!t.max_chunk) return 0;
  return std::max<std::size_t>(1, kLoopCapMargin / (std::size_t(edge) * (ML_OCC_MAX_DISTANCE + 2) + 2));
}

}  // namespace

void VoxelOccupancy::launchLines(cl::CommandQueue& q, cl::Kernel& k, cl_uint lines_arg, std::size_t lines,
                                 unsigned edge, ClPassTimer* timer) {
  std::size_t chunk = 1, global = lines, local = tuning_.wg;
  if (!tuning_.gpu()) {
    // A line is edge voxels (up to 30 reads each): a floor of 16 lines per
    // work-item still splits a 16^3 grid's 256 lines among the work-items.
    chunk = tuning_.cpuChunk(lines, 16);
    if (const std::size_t cap = linesWithinLoopCap(tuning_, edge)) chunk = std::min(chunk, cap);
    global = ceilDiv(lines, chunk);
    local = 1;
  }
  k.setArg(lines_arg, u32(lines));
  k.setArg(lines_arg + 1, u32(chunk));
  launchTimed(q, k, global, local, timer, "vct-occupancy");
}

void VoxelOccupancy::build(cl::CommandQueue& q, unsigned edge, const cl::Buffer& accum, ClPassTimer* timer) {
  if (edge == 0 || edge > ML_VOXEL_MAX_EDGE)
    throw std::invalid_argument("VoxelOccupancy: grid edge " + std::to_string(edge) + " is not in 1.." +
                                std::to_string(ML_VOXEL_MAX_EDGE));
  const std::size_t n = std::size_t(edge) * edge * edge;
  requireBuffer(accum, n * sizeof(gpu::VoxelAccum), "VoxelOccupancy accumulation buffer");
  if (n > capacity_) {
    buffer_ = tmp_ = cl::Buffer();  // release first: the old and new buffers need not coexist
    buffer_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, n);
    tmp_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, n);
    capacity_ = n;
  }
  if (!rows_()) {
    const compute::FittedProgram fitted =
        compute::buildFitted(env_, tuning_, "vct/vct_occupancy.cl", "voxel occupancy");
    tuning_.wg = fitted.wg;  // GPU shape: the group size the compiled kernels accept here
    rows_ = cl::Kernel(fitted.program, "distance_rows");
    lines_ = cl::Kernel(fitted.program, "distance_lines");
  }
  const std::size_t lines = std::size_t(edge) * edge;
  setArgs(rows_, accum, cl_uint(edge), buffer_);
  launchLines(q, rows_, 3, lines, edge, timer);
  setArgs(lines_, buffer_, tmp_, cl_uint(edge), cl_uint(edge));
  launchLines(q, lines_, 4, lines, edge, timer);
  setArgs(lines_, tmp_, buffer_, cl_uint(edge), u32(lines));
  launchLines(q, lines_, 4, lines, edge, timer);
  edge_ = edge;
}

}  // namespace ml::vct
