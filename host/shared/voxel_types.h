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
namespace ml::gpu {
#endif

/* Largest level-0 edge: keeps every offset and index of all levels in 32 bits
 * (512^3 * 8/7 < 2^32). */
#define ML_VOXEL_MAX_EDGE 512u

typedef struct VoxelGridParams {
  ml_float4 origin_voxel_size;
  ml_uint edge;   /* level-0 voxels per axis, a power of two <= ML_VOXEL_MAX_EDGE */
  ml_uint levels; /* 1 .. log2(edge) + 1 */
  ml_uint pad0;
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
}  // namespace ml::gpu
#endif
#endif
