/* The occupancy hierarchy of a level-0 voxel grid (layout:
 * voxel_occupancy.h), which the voxel-shadow march reads to skip empty space.
 *   occupancy_voxels: level 0, one word (32 voxels) per item, a bit per
 *     voxel with a non-zero VoxelAccum count;
 *   occupancy_reduce: level l + 1 from level l of the same buffer, one word
 *     (32 cells) per item, a bit per 4^3 block of level-l cells with any bit
 *     set (blocks clipped at the far faces).
 * Items are words; shapes as in vct_common.cl. The C++ twin is
 * host/vct/OccupancyTwin.hpp (bit for bit). */
#include "vct_common.cl"
#include "voxel_types.h"
#include "voxel_occupancy.h"

__kernel VCT_ATTR void occupancy_voxels(__global const VoxelAccum* accum, uint n_voxels, __global uint* occ,
                                        uint words, uint chunk) {
  uint b, e;
  item_range(words, chunk, &b, &e);
  for (uint w = b; w < e; ++w) {
    const uint first = w * 32u, last = min(first + 32u, n_voxels);
    uint bits = 0u;
    for (uint i = first; i < last; ++i) bits |= (accum[i].albedo_count[3] != 0u ? 1u : 0u) << (i - first);
    occ[w] = bits;
  }
}

/* Any bit set among the level-l cells of block (x, y, z) of level l + 1. */
ML_INLINE uint block_any(__global const uint* src, uint src_edge, uint x, uint y, uint z) {
  const uint s = 1u << ML_OCC_BLOCK_LOG2;
  const uint x0 = x * s, x1 = min(x0 + s, src_edge), y1 = min(y * s + s, src_edge), z1 = min(z * s + s, src_edge);
  for (uint sz = z * s; sz < z1; ++sz)
    for (uint sy = y * s; sy < y1; ++sy)
      for (uint sx = x0; sx < x1; ++sx) {
        const uint c = sx + src_edge * (sy + src_edge * sz);
        if ((src[c >> 5] >> (c & 31u)) & 1u) return 1u;
      }
  return 0u;
}

__kernel VCT_ATTR void occupancy_reduce(__global uint* occ, uint src_offset, uint src_edge, uint dst_offset,
                                        uint dst_edge, uint words, uint chunk) {
  const uint cells = dst_edge * dst_edge * dst_edge;
  uint b, e;
  item_range(words, chunk, &b, &e);
  for (uint w = b; w < e; ++w) {
    const uint first = w * 32u, last = min(first + 32u, cells);
    uint bits = 0u;
    for (uint c = first; c < last; ++c) {
      const uint x = c % dst_edge, y = c / dst_edge % dst_edge, z = c / dst_edge / dst_edge;
      bits |= block_any(occ + src_offset, src_edge, x, y, z) << (c - first);
    }
    occ[dst_offset + w] = bits;
  }
}
