#pragma once
// Voxelization of voxel cone tracing (002's single pass): the scene's triangles,
// projected along their dominant axis and rasterised conservatively, add their
// albedo, normal and a count to every level-0 voxel they cross, as the integer
// sums of host/shared/voxel_types.h (VoxelAccum), into a SharedBuffer the caller
// owns (vct::VoxelVolume's accum) so that the OpenCL kernels (resolve,
// injection, mips) read the result where it lies.
//
// The grid is a cube fitted around the scene's bounds (vct::fitVoxelGrid) or
// one level of 002's camera-centred cascade (vct::VoxelCascade): a toroidal
// grid (VoxelGridParams::wrap) whose voxels are stored where voxel_shift()
// puts them. A region (VoxelRegion: the slabs a scrolled level gained) clears
// and voxelizes only its boxes; the rest of the buffer keeps its sums, and
// only triangles whose bounds reach a box are rasterised.
//
// Conservativeness: triangle dilation by half a voxel in the geometry shader
// (Hasselgren et al., GPU Gems 2 ch. 42) so that every pixel whose square the
// projected triangle touches gets a fragment; in the fragment shader the
// triangle's 2D bounds test (their AABB clip) and then the exact clip of the
// pixel's square against the triangle's edges, whose depth range along the
// column gives the voxels the triangle crosses there. So a voxel is filled
// exactly when the triangle crosses it (up to float rounding at voxel faces).
#include "gl/GlPassTimer.hpp"
#include "gl/SceneGpu.hpp"
#include "gl/ShaderProgram.hpp"
#include "gl/SharedBuffer.hpp"
#include "host/scene/Scene.hpp"
#include "host/shared/voxel_types.h"
#include "host/vct/VoxelRegion.hpp"

namespace ml {

// Throws UserError for a grid whose edge is not a power of two in
// 1..ML_VOXEL_MAX_EDGE, whose levels lie outside 1..log2(edge)+1, or whose
// voxel size is not positive (grids come from vct::fitVoxelGrid or by hand).
void checkVoxelGrid(const gpu::VoxelGridParams& grid);

struct VoxelizeOptions {
  // Off only to show that it matters (tests): without dilation, pixels that a
  // triangle covers only partly, away from their centre, get no fragment.
  bool dilate = true;
};

class VoxelizePass {
 public:
  explicit VoxelizePass(const VoxelizeOptions& options = {});
  ~VoxelizePass();
  VoxelizePass(const VoxelizePass&) = delete;
  VoxelizePass& operator=(const VoxelizePass&) = delete;

  // Clears `accum` (grown to grid.edge^3 VoxelAccums when needed; GL must
  // own it) and voxelizes `scene` into it; a GL pass named `vct-voxelize`.
  // GL owns the buffer afterwards (writes are visible to buffer reads and CL
  // acquisition).
  // With a non-empty `region` only its boxes are cleared and voxelized (the
  // buffer must already hold grid.edge^3 sums).
  void run(const SceneGpu& scene, const gpu::VoxelGridParams& grid, SharedBuffer& accum, GlPassTimer* timer,
           const vct::VoxelRegion& region = {});

 private:
  void bindEmptyFramebuffer(unsigned edge);
  void clear(const gpu::VoxelGridParams& grid, SharedBuffer& accum, const vct::VoxelRegion& region);
  void setRegion(const ShaderProgram& p, const vct::VoxelRegion& region) const;
  VoxelizeOptions options_;
  ShaderProgram program_, clear_;
  GLuint fbo_ = 0;
  unsigned fbo_edge_ = 0;
};

}  // namespace ml
