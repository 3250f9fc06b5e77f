/* The occupancy hierarchy of a level-0 voxel grid, declared once for C++
 * (namespace ml::gpu) and OpenCL C: what the voxel-shadow march
 * (kernels/vct_inject.cl) reads to skip empty space, built by
 * kernels/vct_occupancy.cl (twin: host/vct/OccupancyTwin.hpp).
 *
 * ML_OCC_LEVELS levels of bits in one uint buffer. Level 0 has a bit per
 * voxel of the edge^3 grid, set when the voxel is filled (VoxelAccum count
 * non-zero); level l + 1 has a bit per 4^3 block of level l's cells (edge
 * ceil(e / 4), blocks clipped at the grid's far faces), set when any cell of
 * the block is set. So a level-1 cell is a 4^3 voxel brick, a level-2 cell a
 * 16^3 one. Each level packs its bits x fastest, cell c = x + e * (y + e * z)
 * in bit c % 32 of word c / 32 from the level's first word
 * occupancy_level_offset(); its last word's unused bits are 0. Any edge from
 * 1 to ML_VOXEL_MAX_EDGE works (the grid's is a power of two). */
#ifndef MANYLIGHTS_VOXEL_OCCUPANCY_H
#define MANYLIGHTS_VOXEL_OCCUPANCY_H

#include "gpu_types.h"

#ifndef __OPENCL_VERSION__
namespace ml::gpu {
#define ML_OCC_FN inline constexpr
#else
#define ML_OCC_FN inline
#endif

#define ML_OCC_LEVELS 3u
#define ML_OCC_BLOCK_LOG2 2u /* a level's cell covers 4^3 cells of the level below */

/* Cells per axis of level `level` for a grid of `edge` voxels per axis. */
ML_OCC_FN ml_uint occupancy_level_edge(ml_uint edge, ml_uint level) {
  ml_uint e = edge;
  for (ml_uint l = 0; l < level; ++l) e = (e + (1u << ML_OCC_BLOCK_LOG2) - 1u) >> ML_OCC_BLOCK_LOG2;
  return e;
}

/* Words holding the bits of a level of `e` cells per axis. */
ML_OCC_FN ml_uint occupancy_words(ml_uint e) { return (e * e * e + 31u) / 32u; }

/* First word of level `level` (ML_OCC_LEVELS: the total word count). */
ML_OCC_FN ml_uint occupancy_level_offset(ml_uint edge, ml_uint level) {
  ml_uint offset = 0;
  for (ml_uint l = 0; l < level; ++l) offset += occupancy_words(occupancy_level_edge(edge, l));
  return offset;
}

#undef ML_OCC_FN
#ifndef __OPENCL_VERSION__
}  // namespace ml::gpu
#endif
#endif
