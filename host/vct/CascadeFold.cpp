#include "host/vct/CascadeFold.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/cl/Launch.hpp"
#include "host/compute/FittedProgram.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {
namespace {

bool onLattice(float corner, float voxel) {
  const double k = double(corner) / voxel;
  return std::fabs(k - std::round(k)) < 1e-3;
}

bool cornerOnLattice(const gpu::VoxelGridParams& g) {
  const auto& o = g.origin_voxel_size;
  return onLattice(o.x, o.w) && onLattice(o.y, o.w) && onLattice(o.z, o.w);
}

cl_int4 corner4(long long x, long long y, long long z, bool wrap) {
  return cl_int4{{static_cast<cl_int>(x), static_cast<cl_int>(y), static_cast<cl_int>(z), wrap ? 1 : 0}};
}

}  // namespace

bool foldable(const gpu::VoxelGridParams& fine, const gpu::VoxelGridParams& coarse) {
  if (fine.levels < 2 || fine.origin_voxel_size.w * 2.0f != coarse.origin_voxel_size.w) return false;
  if (!cornerOnLattice(fine) || !cornerOnLattice(coarse)) return false;
  const LatticeCorner f = latticeCorner(fine);
  return f.x % 2 == 0 && f.y % 2 == 0 && f.z % 2 == 0;
}

VoxelBox foldBox(const gpu::VoxelGridParams& fine, const gpu::VoxelGridParams& coarse) {
  const LatticeCorner f = latticeCorner(fine), c = latticeCorner(coarse);
  const long long fl[3] = {f.x / 2, f.y / 2, f.z / 2}, cl[3] = {c.x, c.y, c.z};
  VoxelBox b;
  for (int a = 0; a < 3; ++a) {
    const long long lo = std::max(fl[a], cl[a]), hi = std::min(fl[a] + fine.edge / 2, cl[a] + coarse.edge);
    if (hi <= lo) return VoxelBox{};
    b.lo[a] = static_cast<unsigned>(lo - cl[a]);
    b.hi[a] = static_cast<unsigned>(hi - cl[a]);
  }
  return b;
}

CascadeFold::CascadeFold(const compute::ComputeEnv& env, const compute::Options& options)
    : env_(env), tuning_(compute::resolveTuning(env, options)) {}

void CascadeFold::run(cl::CommandQueue& q, const gpu::VoxelGridParams& fine, const cl::Buffer& fine_radiance,
                      const gpu::VoxelGridParams& coarse, cl::Buffer& coarse_radiance, ClPassTimer* timer) {
  if (!foldable(fine, coarse)) throw std::invalid_argument("CascadeFold: the levels do not nest");
  requireBuffer(fine_radiance, std::size_t(gpu::voxel_level_offset(fine.edge, 2)) * 16, "CascadeFold finer volume");
  requireBuffer(coarse_radiance, std::size_t(coarse.edge) * coarse.edge * coarse.edge * 16,
                "CascadeFold coarser level 0");
  const VoxelBox box = foldBox(fine, coarse);
  const std::size_t rows = std::size_t(box.hi[1] - box.lo[1]) * (box.hi[2] - box.lo[2]);
  if (box.voxels() == 0) return;
  if (!fold_()) {
    const compute::FittedProgram fitted = compute::buildFitted(env_, tuning_, "vct/vct_cascade_fold.cl", "cascade fold");
    tuning_.wg = fitted.wg;
    fold_ = cl::Kernel(fitted.program, "cascade_fold");
  }
  const LatticeCorner f = latticeCorner(fine), c = latticeCorner(coarse);
  setArgs(fold_, fine_radiance, cl_uint(log2Exact(fine.edge)), corner4(f.x / 2, f.y / 2, f.z / 2, fine.wrap != 0),
          coarse_radiance, cl_uint(log2Exact(coarse.edge)), corner4(c.x, c.y, c.z, coarse.wrap != 0),
          cl_uint4{{box.lo[0], box.lo[1], box.lo[2], 0u}},
          cl_uint4{{box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2], 0u}});
  launchTimed(q, fold_, rows, tuning_.gpu() ? tuning_.wg : 1, timer, "vct-fold");
}

}  // namespace ml::vct
