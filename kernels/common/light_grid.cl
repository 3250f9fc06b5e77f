/* The light grid the shaders read, written the same way by every technique
 * whose lists come out of count -> scan -> fill (tiled/, clustered/): one
 * LightRange (offset, count) per cell, cell c's lights at
 * indices[offset .. offset + count). Needs gpu_types.h (LightRange).
 *
 *   write_grid   a work-item per cell: (offsets[c], counts[c]) -> grid[c]
 */
#ifndef ML_COMMON_LIGHT_GRID_CL
#define ML_COMMON_LIGHT_GRID_CL

__kernel void write_grid(__global const uint* offsets, __global const uint* counts, uint n_tiles,
                         __global LightRange* grid) {
  const uint t = get_global_id(0);
  if (t >= n_tiles) return;
  LightRange r;
  r.offset = offsets[t];
  r.count = counts[t];
  grid[t] = r;
}

#endif /* ML_COMMON_LIGHT_GRID_CL */
