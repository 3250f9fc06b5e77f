// Clustered shading: the fragment's cluster comes from the per-pixel map that
// the key/unique kernels wrote (kernels/cluster_keys.cl), so the shader never
// recomputes a key and cannot disagree with the assignment about the slice.
struct LightList {
  uint offset;
  uint count;
};
layout(std430, binding = 1) readonly buffer LightIndexBuffer { uint light_indices[]; };
layout(std430, binding = 2) readonly buffer ClusterRangeBuffer { uvec2 cluster_ranges[]; };
layout(std430, binding = 3) readonly buffer ClusterMapBuffer { uint cluster_map[]; };
uniform uint u_cluster_width;
LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord) {
  uvec2 p = uvec2(frag_coord);
  uint c = cluster_map[p.y * u_cluster_width + p.x];
  if (c == 0xffffffffu) return LightList(0u, 0u);
  uvec2 r = cluster_ranges[c];
  return LightList(r.x, r.y);
}
uint lightIndexAt(LightList list, uint i) { return light_indices[list.offset + i]; }
