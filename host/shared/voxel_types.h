/* The voxel grid of voxel cone tracing, declared once for C++ (namespace
 * ml::gpu), OpenCL C and, mirrored in std430 blocks, GLSL.
 *
 * A cube of `edge` = 2^k voxels per axis at level 0; world-space corner
 * origin_voxel_size.xyz, level-0 voxel edge length origin_voxel_size.w.
 * Level l has e = edge >> l voxels per axis. In every buffer that holds all
 * levels, voxel (x, y, z) of level l lives at
 *     voxel_level_offset(edge, l) + x + e * (y + e * z)       (x fastest).
 * Level 0 of the voxelization is a VoxelAccum per voxel; the resolved,
 * lit and mip-mapped volume is a separate buffer (see host/vct/). */
#ifndef MANYLIGHTS_VOXEL_TYPES_H
#define MANYLIGHTS_VOXEL_TYPES_H

#include "gpu_types.h"
#ifndef __OPENCL_VERSION__
#include <cmath>
#endif

#ifndef __OPENCL_VERSION__
namespace ml::gpu {
#endif

/* Largest level-0 edge: keeps every offset and index of all levels in 32 bits
 * (512^3 * 8/7 < 2^32). */
#define ML_VOXEL_MAX_EDGE 512u

typedef struct VoxelGridParams {
  ml_float4 origin_voxel_size;
  ml_uint edge;   /* level-0 voxels per axis, a power of two <= ML_VOXEL_MAX_EDGE */
  ml_uint levels; /* 1 .. log2(edge) + 1 */
  /* 0: voxel v of the window (0..edge-1 per axis) is stored at v. 1: toroidal
   * (a camera-centred cascade level, host/vct/VoxelCascade.hpp): the corner
   * lies on the lattice of the voxel size, corner = k * voxel size with
   * integer k, and v is stored at (v + k) mod edge per axis, so a voxel keeps
   * its place while the window scrolls; k is a multiple of 2^(levels - 1), so
   * level l's voxel (v + k / 2^l) mod (edge >> l) has its 8 children at level
   * l - 1 in the same places as an unscrolled grid's (the mips need no
   * change). voxel_shift() gives k mod edge. A toroidal voxel's centre is
   * (k + v + 0.5) * voxel size, from its lattice index, so a voxel that
   * stays in the window while it scrolls keeps its bits. */
  ml_uint wrap;
  ml_uint pad1;
} VoxelGridParams;
ML_STATIC_ASSERT(sizeof(VoxelGridParams) == 32, "VoxelGridParams layout changed: update kernels and GLSL");

/* What voxelization writes per level-0 voxel: sums over the fragments that
 * covered it, in integers so that the result does not depend on the order in
 * which fragments arrive (GLSL atomicAdd; 002 averages with a spinlock, which
 * is order-dependent and can livelock on software GL).
 *   albedo_count.xyz: sum of round(albedo * 255); albedo_count.w: fragments;
 *   normal_sum.xyz:   sum of round(world normal * 1024); normal_sum.w: unused.
 * GLSL mirror: struct { uvec4 albedo_count; ivec4 normal_sum; }. */
typedef struct VoxelAccum {
  ml_uint albedo_count[4];
  ml_int normal_sum[4];
} VoxelAccum;
ML_STATIC_ASSERT(sizeof(VoxelAccum) == 32, "VoxelAccum layout changed: update kernels and GLSL");

#define ML_VOXEL_ALBEDO_SCALE 255
#define ML_VOXEL_NORMAL_SCALE 1024

/* First voxel of level l in a buffer holding all levels of a grid of this edge. */
#ifdef __OPENCL_VERSION__
inline uint voxel_level_offset(uint edge, uint level) {
#else
inline constexpr ml_uint voxel_level_offset(ml_uint edge, ml_uint level) {
#endif
  ml_uint offset = 0;
  for (ml_uint l = 0; l < level; ++l) {
    ml_uint e = edge >> l;
    offset += e * e * e;
  }
  return offset;
}

/* The radiance/opacity volume (host/vct/VoxelVolume.hpp): one float4 per
 * voxel of every level at voxel_level_offset(), premultiplied radiance in
 * rgb, opacity in a.
 * The anisotropic volume (Crassin 2011): levels >= 1 only, 6 float4 per
 * voxel, one per direction of travel of a cone through it (+X, -X, +Y, -Y,
 * +Z, -Z: ML_VOXEL_DIR_*). Level l's block starts at
 *     6 * (voxel_level_offset(edge, l) - edge^3)
 * and holds the 6 directions one after another, each a full e^3 volume in
 * the same x-fastest order, so that GL can unpack each direction of a level
 * as one 3D texture. voxel_aniso_index() gives the float4 index. */
#define ML_VOXEL_DIRECTIONS 6u
#define ML_VOXEL_DIR_POS_X 0u
#define ML_VOXEL_DIR_NEG_X 1u
#define ML_VOXEL_DIR_POS_Y 2u
#define ML_VOXEL_DIR_NEG_Y 3u
#define ML_VOXEL_DIR_POS_Z 4u
#define ML_VOXEL_DIR_NEG_Z 5u

#ifdef __OPENCL_VERSION__
inline uint voxel_aniso_index(uint edge, uint level, uint dir, uint voxel) {
#else
inline constexpr ml_uint voxel_aniso_index(ml_uint edge, ml_uint level, ml_uint dir, ml_uint voxel) {
#endif
  ml_uint e = edge >> level;
  return ML_VOXEL_DIRECTIONS * (voxel_level_offset(edge, level) - edge * edge * edge) + dir * e * e * e + voxel;
}

#ifndef __OPENCL_VERSION__
/* A toroidal grid's corner as a lattice index k (corner / voxel size,
 * rounded: the corner is k * voxel size exactly), and where window voxel 0
 * is stored, k mod edge per axis (0 for an unscrolled grid). Kernels and
 * shaders get them as arguments. */
struct VoxelCorner {
  ml_int x, y, z;
};
inline VoxelCorner voxel_corner(const VoxelGridParams& g) {
  if (!g.wrap) return VoxelCorner{0, 0, 0};
  const float o[3] = {g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z};
  ml_int k[3];
  for (int c = 0; c < 3; ++c) k[c] = static_cast<ml_int>(std::lround(o[c] / g.origin_voxel_size.w));
  return VoxelCorner{k[0], k[1], k[2]};
}
struct VoxelShift {
  ml_uint x, y, z;
};
inline VoxelShift voxel_shift(const VoxelGridParams& g) {
  const VoxelCorner k = voxel_corner(g);
  const ml_uint mask = g.edge - 1u;  /* edge is a power of two: & is mod for negative k too */
  return VoxelShift{static_cast<ml_uint>(k.x) & mask, static_cast<ml_uint>(k.y) & mask,
                    static_cast<ml_uint>(k.z) & mask};
}
/* The window coordinates of stored voxel i (kernels/vct/vct_inject.cl's
 * window_voxel()): its storage coordinates minus the shift, mod edge. */
struct VoxelWindow {
  ml_uint x, y, z;
};
inline VoxelWindow voxel_window(const VoxelGridParams& g, ml_uint i) {
  const VoxelShift s = voxel_shift(g);
  const ml_uint e = g.edge, mask = e - 1u;
  return VoxelWindow{(i % e - s.x) & mask, (i / e % e - s.y) & mask, (i / e / e - s.z) & mask};
}
}  // namespace ml::gpu
#endif
#endif
