#pragma once
// Mips across the levels of the camera-centred cascade (--vct-fold,
// VoxelCascade.hpp): after a finer level's own mips, the coarser level's
// level-0 voxels that the finer window covers take the opacity of the finer
// level's mip level 1 voxel at the same place, keeping their own colour
// (kernels/vct/vct_cascade_fold.cl), before the coarser level's own mips. A
// coarse voxel voxelized on its own is opaque wherever a triangle touches
// it; the finer mip holds the coverage of its 8 children, so where both
// levels see the scene their opacities agree. The colour stays the coarse
// voxel's own (lit at its centre with its own normal): the isotropic mip's
// colour averages a wall's lit face with its dark back (the default scene's
// flight, 2 x 64^3: the whole mip voxel folded made the indirect light 15%
// darker and the error 0.20-0.27 against 0.15-0.20 unfolded; docs/vct.md).
// Contract:
//  - foldable(fine, coarse): the finer voxel is half the coarser one, the
//    finer level has a mip level 1, and both corners lie on their lattices
//    (the finer one's even), so lattice cells nest; placeCascade's levels are.
//  - foldBox(): the box of the coarser window (window coordinates) the finer
//    window covers, clipped to it; empty (voxels() == 0) when they miss.
//  - CascadeFold::run(): rewrites that box of the coarser level 0 and
//    nothing else, each voxel (own colour at the mip's opacity; the mip's
//    colour where the voxel is empty); std::invalid_argument for levels that are not foldable or buffers
//    smaller than their grids. Timed as "vct-fold". C++ twin:
//    CascadeFoldTwin.hpp, equal bit for bit. Not thread-safe.
#include <CL/opencl.hpp>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/shared/voxel_types.h"
#include "host/vct/VoxelCascade.hpp"  // LatticeCorner
#include "host/vct/VoxelRegion.hpp"

namespace ml::vct {

bool foldable(const gpu::VoxelGridParams& fine, const gpu::VoxelGridParams& coarse);
VoxelBox foldBox(const gpu::VoxelGridParams& fine, const gpu::VoxelGridParams& coarse);

class CascadeFold {
 public:
  explicit CascadeFold(const compute::ComputeEnv& env, const compute::Options& options = {});

  void run(cl::CommandQueue& q, const gpu::VoxelGridParams& fine, const cl::Buffer& fine_radiance,
           const gpu::VoxelGridParams& coarse, cl::Buffer& coarse_radiance, ClPassTimer* timer = nullptr);

 private:
  compute::ComputeEnv env_;
  compute::Tuning tuning_;
  cl::Kernel fold_;
};

}  // namespace ml::vct
