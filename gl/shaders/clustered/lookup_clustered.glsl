// Clustered shading: the fragment's cluster comes from the per-pixel map that
// the key/unique kernels wrote (kernels/clustered/cluster_keys.cl), so the shader never
// recomputes a key and cannot disagree with the assignment about the slice.
// A cluster's list is a run of hit records (kernels/clustered/cluster_assign.cl): the
// first leaf slot and a mask of the leaf's lights that reach the cluster.
#include "shading_bindings.h"
struct LightList {
  uint record;      // next record
  uint record_end;
  uint slot;        // leaf slot of the current record
  uint mask;        // its lights not yet visited
};
layout(std430, binding = ML_BINDING_CLUSTER_RECORDS) readonly buffer ClusterRecordBuffer { uvec2 cluster_records[]; };
layout(std430, binding = ML_BINDING_CLUSTER_RANGES) readonly buffer ClusterRangeBuffer { uvec2 cluster_ranges[]; };
layout(std430, binding = ML_BINDING_CLUSTER_MAP) readonly buffer ClusterMapBuffer { uint cluster_map[]; };
layout(std430, binding = ML_BINDING_CLUSTER_LEAF_LIGHTS) readonly buffer LeafLightBuffer { uint leaf_lights[]; };
uniform uint u_cluster_width;
LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord) {
  uvec2 p = uvec2(frag_coord);
  uint c = cluster_map[p.y * u_cluster_width + p.x];
  if (c == 0xffffffffu) return LightList(0u, 0u, 0u, 0u);
  uvec2 r = cluster_ranges[c];
  return LightList(r.x, r.x + r.y, 0u, 0u);
}
bool listEnded(LightList list) { return list.mask == 0u && list.record == list.record_end; }
bool nextLight(inout LightList list, out uint light_index) {
  light_index = 0u;
  if (list.mask == 0u) {
    if (list.record == list.record_end) return false;
    uvec2 rec = cluster_records[list.record++];
    list.slot = rec.x;
    list.mask = rec.y;  // never 0: only leaves with hits are recorded
  }
  int bit = findLSB(list.mask);
  list.mask &= list.mask - 1u;
  light_index = leaf_lights[list.slot + uint(bit)];
  return true;
}
