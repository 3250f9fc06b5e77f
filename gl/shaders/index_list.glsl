// A light list as a run of light indices, (offset, count) into the index list
// at SSBO binding 1: tiled and hashed shading (their lookup_*.glsl include it
// and return LightLists from lightListFor).
struct LightList {
  uint offset;
  uint count;
};
layout(std430, binding = 1) readonly buffer LightIndexBuffer { uint light_indices[]; };
bool nextLight(inout LightList list, out uint light_index) {
  light_index = 0u;
  if (list.count == 0u) return false;
  light_index = light_indices[list.offset++];
  --list.count;
  return true;
}
