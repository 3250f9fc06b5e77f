// Hashed shading (thesis Listing 8): walk the linkless octree, one perfect
// spatial hash per layer, from the start depth down until the point's node is
// a leaf. Mirrors hashed::LinklessOctree::lookup() (host/hashed/) line for
// line; buffers as packed by HashedAssigner:
//   1 light index list, 2 header, 3 offset tables (x | y << 8 | z << 16),
//   4 description slots (uvec2: key x | y << 16, z | leaf << 16 | filled << 24),
//   5 light-data slots (uvec4: key x | y << 16, z, offset, count).
// An empty slot has 0xFFFFFFFF as its first word, so a key that is absent
// never matches: it reads as "no lights". Index list entries are
// light | octant mask << 24 (host/hashed/OctantMask.hpp): a light is
// evaluated only if it reaches the point's octant of its leaf cell.
// The layer loop below runs at most hs_info.z (the layer count) times.
#include "shading_bindings.h"
struct LightList {
  uint offset;
  uint end;
  uint octant_bit;  // 1 << (24 + the point's octant)
};
layout(std430, binding = ML_BINDING_HASHED_INDICES) readonly buffer LightIndexBuffer { uint light_indices[]; };
bool listEnded(LightList list) { return list.offset >= list.end; }
// One entry per call, no loop (see LightAssigner.hpp): false at the end and
// for an entry whose light does not reach the point's octant.
bool nextLight(inout LightList list, out uint light_index) {
  light_index = 0u;
  if (list.offset >= list.end) return false;
  uint e = light_indices[list.offset++];
  light_index = e & 0xFFFFFFu;
  return (e & list.octant_bit) != 0u;
}
layout(std430, binding = ML_BINDING_HASHED_HEADER) readonly buffer HashedHeader {
  vec4 hs_origin_scale;  // octree origin (xyz), cells per world unit (w)
  uvec4 hs_info;         // depth, start depth, layer count, unused
  // Per layer i: [4i] description table (m.xyz, slot base), [4i+1] its
  // offsets (r.xyz, offset base), [4i+2] and [4i+3] the same for light data.
  uvec4 hs_tables[];
};
layout(std430, binding = ML_BINDING_HASHED_OFFSETS) readonly buffer HashedOffsets { uint hs_offsets[]; };
layout(std430, binding = ML_BINDING_HASHED_DESC) readonly buffer HashedDesc { uvec2 hs_desc[]; };
layout(std430, binding = ML_BINDING_HASHED_DATA) readonly buffer HashedData { uvec4 hs_data[]; };

// h(p) = (p mod m + Phi[p mod r]) mod m, flattened, plus the table's base.
uint hsSlot(uvec3 p, uvec4 m, uvec4 r) {
  uvec3 o = p % r.xyz;
  uint phi = hs_offsets[r.w + o.x + r.x * (o.y + r.y * o.z)];
  uvec3 off = uvec3(phi & 0xFFu, (phi >> 8) & 0xFFu, (phi >> 16) & 0xFFu);
  uvec3 h = (p % m.xyz + off) % m.xyz;
  return m.w + h.x + m.x * (h.y + m.y * h.z);
}

LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord) {
  LightList none = LightList(0u, 0u, 0u);
  vec3 q = (world_pos - hs_origin_scale.xyz) * hs_origin_scale.w;
  uint depth = hs_info.x;
  float n = float(1u << depth);
  if (!(all(greaterThanEqual(q, vec3(0.0))) && all(lessThan(q, vec3(n))))) return none;
  uvec3 cell = min(uvec3(q), uvec3((1u << depth) - 1u));
  for (uint i = 0u; i < hs_info.z; ++i) {
    uint d = hs_info.y + i;
    uvec3 cur = cell >> (depth - d);
    uvec3 nxt = cell >> (depth - d - 1u);
    uvec2 e = hs_desc[hsSlot(cur, hs_tables[4u * i], hs_tables[4u * i + 1u])];
    if (e.x != (cur.x | (cur.y << 16)) || (e.y & 0xFFFFu) != cur.z) return none;  // no node: no lights
    uvec3 k = nxt & 1u;
    uint bit = k.x + 2u * k.y + 4u * k.z;
    if (((e.y >> (16u + bit)) & 1u) != 0u) {      // the child is a leaf
      if (((e.y >> (24u + bit)) & 1u) != 0u) {    // ... with lights
        uvec4 dt = hs_data[hsSlot(nxt, hs_tables[4u * i + 2u], hs_tables[4u * i + 3u])];
        if (dt.x == (nxt.x | (nxt.y << 16)) && (dt.y & 0xFFFFu) == nxt.z) {
          uvec3 h = uvec3(q * 2.0) & 1u;  // the octant (exact: doubling is exact)
          return LightList(dt.z, dt.z + dt.w, 1u << (24u + h.x + 2u * h.y + 4u * h.z));
        }
      }
      return none;
    }
  }
  return none;
}

