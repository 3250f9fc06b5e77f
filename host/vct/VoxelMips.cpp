#include "host/vct/VoxelMips.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/cl/Launch.hpp"
#include "host/compute/FittedProgram.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {


namespace {

void checkGrid(const gpu::VoxelGridParams& g) {
  VoxelGridSettings s;
  s.voxels = g.edge;
  s.levels = g.levels;
  checkVoxelGrid(s);
}

}  // namespace

VoxelMips::VoxelMips(const compute::ComputeEnv& env, const compute::Options& options)
    : env_(env), tuning_(compute::resolveTuning(env, options)) {}

void VoxelMips::build() {
  if (iso_()) return;
  // GPU shape: the group size the compiled kernels accept on this device.
  const compute::FittedProgram fitted = compute::buildFitted(env_, tuning_, "vct/vct_mips.cl", "voxel mips");
  tuning_.wg = fitted.wg;
  iso_ = cl::Kernel(fitted.program, "mip_iso");
  aniso_ = cl::Kernel(fitted.program, "mip_aniso");
}

// Launches `k` (arguments 0 .. first_arg - 1 set by the caller) once per run
// of up to kTreeDepth levels, each top parent's subtree in one work-item (CPU
// shape) or work-group (GPU shape): one launch for a grid of up to 4 levels,
// where one launch per level made small grids launch-bound.
void VoxelMips::launchTrees(cl::CommandQueue& q, cl::Kernel& k, cl_uint first_arg, const gpu::VoxelGridParams& g,
                            ClPassTimer* timer) {
  const unsigned edge_log2 = log2Exact(g.edge);
  for (unsigned l0 = 0, depth = 0; l0 + 1 < g.levels; l0 += depth) {
    depth = std::min(kTreeDepth, g.levels - 1 - l0);
    const unsigned top_log2 = edge_log2 - l0 - depth;  // the top level's edge
    // GPU: top parents per work-group, enough that the first level's
    // blocks (8^(depth - 1) parents each) fill it; CPU: top-level z-slices
    // per work-item (a few per core).
    std::size_t global = 0, local = 1, tops = 1;
    if (tuning_.gpu()) {
      local = tuning_.wg;
      tops = std::max<std::size_t>(1, local >> (3 * (depth - 1)));
      global = ceilDiv(std::size_t(1) << (3 * top_log2), tops) * local;
    } else {
      const std::size_t slices = std::size_t(1) << top_log2;
      tops = ceilDiv(slices, std::min<std::size_t>(slices, tuning_.chunks));
      global = ceilDiv(slices, tops);
    }
    cl_uint a = first_arg;
    for (cl_uint v : {cl_uint(edge_log2), cl_uint(l0), cl_uint(depth), u32(tops)}) k.setArg(a++, v);
    launchTimed(q, k, global, local, timer, "vct-mips");
  }
}

void VoxelMips::isotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, cl::Buffer& radiance,
                          ClPassTimer* timer) {
  checkGrid(g);
  requireBuffer(radiance, std::size_t(gpu::voxel_level_offset(g.edge, g.levels)) * 16,
                               "VoxelMips radiance volume");
  build();
  setArgs(iso_, radiance);
  launchTrees(q, iso_, 1, g, timer);
}

void VoxelMips::anisotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& radiance,
                            cl::Buffer& aniso, ClPassTimer* timer) {
  checkGrid(g);
  requireBuffer(radiance, std::size_t(g.edge) * g.edge * g.edge * 16, "VoxelMips radiance level 0");
  requireBuffer(aniso, std::size_t(gpu::voxel_aniso_index(g.edge, g.levels, 0, 0)) * 16,
                               "VoxelMips anisotropic volume");
  build();
  setArgs(aniso_, radiance, aniso);
  launchTrees(q, aniso_, 2, g, timer);
}

}  // namespace ml::vct
