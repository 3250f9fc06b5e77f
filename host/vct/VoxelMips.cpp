#include "host/vct/VoxelMips.hpp"

#include <stdexcept>

#include "host/compute/Detail.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {

using compute::detail::u32;

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
  cl::Program p = compute::detail::buildShaped(env_, tuning_, "vct_mips.cl");
  iso_ = cl::Kernel(p, "mip_iso");
  aniso_ = cl::Kernel(p, "mip_aniso");
}

void VoxelMips::shapeFor(std::size_t n, std::size_t& global, std::size_t& local, std::size_t& chunk) const {
  if (tuning_.gpu()) {
    local = tuning_.wg;
    global = n;
    chunk = 1;
  } else {
    local = 1;
    chunk = tuning_.cpuChunk(n);
    global = compute::detail::ceilDiv(n, chunk);
  }
}

void VoxelMips::isotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, cl::Buffer& radiance,
                          ClPassTimer* timer) {
  checkGrid(g);
  compute::detail::checkBuffer(radiance, std::size_t(gpu::voxel_level_offset(g.edge, g.levels)) * 16,
                               "VoxelMips radiance volume");
  build();
  for (unsigned l = 1; l < g.levels; ++l) {
    const unsigned ep_log2 = log2Exact(g.edge >> l);
    const std::size_t n = std::size_t(1) << (3 * ep_log2);
    std::size_t global, local, chunk;
    shapeFor(n, global, local, chunk);
    compute::detail::setArgs(iso_, radiance, gpu::voxel_level_offset(g.edge, l - 1), gpu::voxel_level_offset(g.edge, l),
                             cl_uint(ep_log2), u32(n), u32(chunk));
    compute::detail::launch(q, iso_, global, local, timer, "vct-mips");
  }
}

void VoxelMips::anisotropic(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& radiance,
                            cl::Buffer& aniso, ClPassTimer* timer) {
  checkGrid(g);
  compute::detail::checkBuffer(radiance, std::size_t(g.edge) * g.edge * g.edge * 16, "VoxelMips radiance level 0");
  compute::detail::checkBuffer(aniso, std::size_t(gpu::voxel_aniso_index(g.edge, g.levels, 0, 0)) * 16,
                               "VoxelMips anisotropic volume");
  build();
  for (unsigned l = 1; l < g.levels; ++l) {
    const unsigned ep_log2 = log2Exact(g.edge >> l);
    const std::size_t n = std::size_t(1) << (3 * ep_log2);
    const bool from_iso = l == 1;
    std::size_t global, local, chunk;
    shapeFor(n, global, local, chunk);
    compute::detail::setArgs(aniso_, from_iso ? radiance : aniso,
                             from_iso ? 0u : gpu::voxel_aniso_index(g.edge, l - 1, 0, 0), from_iso ? 0u : u32(n * 8),
                             aniso, gpu::voxel_aniso_index(g.edge, l, 0, 0), cl_uint(ep_log2), u32(n), u32(chunk));
    compute::detail::launch(q, aniso_, global, local, timer, "vct-mips");
  }
}

}  // namespace ml::vct
