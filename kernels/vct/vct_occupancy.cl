/* The empty-space distance volume of a level-0 voxel grid (layout:
 * voxel_occupancy.h), which the voxel-shadow march reads to skip empty
 * space. Three passes, items are lines of the grid along one axis:
 *   distance_rows: along x, from the accumulation buffer: the distance along
 *     the row to its nearest filled voxel (a forward and a backward sweep);
 *   distance_lines (twice: along y, then z): f'(i) = min over j of
 *     max(|i - j|, f(j)) along the line, searched outward from i and stopped
 *     once |i - j| reaches the best so far (nothing farther can beat it).
 * Every value clamped to ML_OCC_MAX_DISTANCE. Shapes as in vct_common.cl.
 * The C++ twin is host/vct/OccupancyTwin.hpp (equal byte for byte). */
#include "vct/vct_common.cl"
#include "voxel_types.h"
#include "voxel_occupancy.h"

__kernel VCT_ATTR void distance_rows(__global const VoxelAccum* accum, uint edge, __global uchar* out, uint rows,
                                     uint chunk) {
  uint b, e;
  item_range(rows, chunk, &b, &e);
  for (uint r = b; r < e; ++r) {
    const uint base = r * edge;
    uint d = ML_OCC_MAX_DISTANCE;
    for (uint x = 0; x < edge; ++x) {
      d = accum[base + x].albedo_count[3] != 0u ? 0u : min(d + 1u, ML_OCC_MAX_DISTANCE);
      out[base + x] = (uchar)d;
    }
    d = ML_OCC_MAX_DISTANCE;
    for (uint x = edge; x-- > 0u;) {
      d = out[base + x] == 0u ? 0u : min(d + 1u, ML_OCC_MAX_DISTANCE);
      out[base + x] = (uchar)min(d, (uint)out[base + x]);
    }
  }
}

/* Line l along the axis of `stride` (edge: y, edge^2: z) starts at voxel
 * (l % stride) + (l / stride) * stride * edge. */
__kernel VCT_ATTR void distance_lines(__global const uchar* in, __global uchar* out, uint edge, uint stride,
                                      uint lines, uint chunk) {
  uint b, e;
  item_range(lines, chunk, &b, &e);
  for (uint l = b; l < e; ++l) {
    const uint base = l % stride + l / stride * stride * edge;
    for (uint i = 0; i < edge; ++i) {
      uint best = in[base + i * stride];
      for (uint r = 1u; r < best; ++r) {
        if (i >= r) best = min(best, max(r, (uint)in[base + (i - r) * stride]));
        if (i + r < edge) best = min(best, max(r, (uint)in[base + (i + r) * stride]));
      }
      out[base + i * stride] = (uchar)best;
    }
  }
}
