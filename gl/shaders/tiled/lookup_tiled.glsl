// Tiled shading: the fragment's screen tile holds (offset, count) into the
// light index list (built by kernels/tiled/tiled_light_culling.cl).
#include "shading_bindings.h"
struct LightList {
  uint offset;
  uint count;
};
layout(std430, binding = ML_BINDING_TILED_INDICES) readonly buffer LightIndexBuffer { uint light_indices[]; };
bool listEnded(LightList list) { return list.count == 0u; }
bool nextLight(inout LightList list, out uint light_index) {
  light_index = 0u;
  if (list.count == 0u) return false;
  light_index = light_indices[list.offset++];
  --list.count;
  return true;
}
layout(std430, binding = ML_BINDING_TILED_GRID) readonly buffer TileGridBuffer { uvec2 tile_grid[]; };
uniform uint u_tiles_x;
LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord) {
  uvec2 tile = uvec2(frag_coord) / TILE_SIZE;
  uvec2 r = tile_grid[tile.y * u_tiles_x + tile.x];
  return LightList(r.x, r.y);
}

