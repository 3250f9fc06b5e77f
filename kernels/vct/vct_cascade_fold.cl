/* Folds a finer level of the camera-centred cascade into the next coarser
 * one (host/vct/CascadeFold.hpp): where the finer window lies, the coarser
 * level's level-0 voxel takes the opacity of the finer level's mip level 1
 * voxel at the same place (the same lattice cell: the finer voxel is half
 * the coarser one), keeping its own colour (fold_voxel). Both levels' addressing as voxel_types.h states it: lattice index J
 * of the coarser voxel at window coordinate w is corner + w; a toroidal
 * level stores it at J mod edge, an unscrolled one at w.
 *   fine:   every level of the finer radiance volume; fine_log2 its level-0
 *           edge; fine_half: its corner / 2 (its mip 1's lattice corner) xyz,
 *           wrap w.
 *   coarse: level 0 of the coarser volume; coarse_log2 its edge; coarse_corner
 *           its lattice corner xyz, wrap w.
 *   box_lo, box_size: the coarser window's box to fill (CascadeFold's
 *           foldBox: inside both windows).
 * One work-item per row of the box along x, in both kernel shapes: at most
 * (edge / 2)^3 voxels, each read and written once, have nothing to share
 * between items or to split further; the GPU shape only sets the group size
 * (VCT_ATTR). C++ twin: host/vct/CascadeFoldTwin.hpp, equal bit for bit
 * (FP_CONTRACT off; divisions correctly rounded where the device can,
 * ClRuntime). */
#pragma OPENCL FP_CONTRACT OFF
#include "vct/vct_common.cl"
#include "gpu_types.h"
#include "voxel_types.h"

/* Where lattice index j of the coarser level's voxel size lives in a level
 * of edge 1 << log2 whose window starts at `corner`. */
ML_INLINE uint stored_at(int j, int corner, int wrap, uint log2) {
  return wrap ? ((uint)j & ((1u << log2) - 1u)) : (uint)(j - corner);
}

/* The coarser voxel's own colour (radiance over opacity: lit at its centre
 * with its own normal, the face it shows) at the finer mip's opacity (the
 * coverage of its children); the mip's colour where the voxel has none. */
ML_INLINE float4 fold_voxel(float4 own, float4 fine) {
  const float3 colour = own.w > 0.0f ? own.xyz / own.w : (fine.w > 0.0f ? fine.xyz / fine.w : (float3)(0.0f));
  return (float4)(colour * fine.w, fine.w);
}

__kernel VCT_ATTR void cascade_fold(__global const float4* fine, uint fine_log2, int4 fine_half,
                                    __global float4* coarse, uint coarse_log2, int4 coarse_corner, uint4 box_lo,
                                    uint4 box_size) {
  const uint row = get_global_id(0);
  if (row >= box_size.y * box_size.z) return;
  const int jy = coarse_corner.y + (int)(box_lo.y + row % box_size.y);
  const int jz = coarse_corner.z + (int)(box_lo.z + row / box_size.y);
  const uint f1 = fine_log2 - 1u;  /* the finer level's mip 1 */
  const uint fy = stored_at(jy, fine_half.y, fine_half.w, f1), fz = stored_at(jz, fine_half.z, fine_half.w, f1);
  const uint cy = stored_at(jy, coarse_corner.y, coarse_corner.w, coarse_log2);
  const uint cz = stored_at(jz, coarse_corner.z, coarse_corner.w, coarse_log2);
  __global const float4* src = fine + (1u << (3u * fine_log2)) + ((fy + (fz << f1)) << f1);
  __global float4* dst = coarse + ((cy + (cz << coarse_log2)) << coarse_log2);
  for (uint i = 0; i < box_size.x; ++i) {
    const int jx = coarse_corner.x + (int)(box_lo.x + i);
    const uint ci = stored_at(jx, coarse_corner.x, coarse_corner.w, coarse_log2);
    dst[ci] = fold_voxel(dst[ci], src[stored_at(jx, fine_half.x, fine_half.w, f1)]);
  }
}
