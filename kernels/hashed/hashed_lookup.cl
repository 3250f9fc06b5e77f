/* Hashed shading's light-list lookup in OpenCL C: gl/shaders/hashed/lookup_hashed.glsl
 * line for line (and so hashed::LinklessOctree::lookup(), which tests hold it
 * to). Buffers as the GLSL binds them (LinklessOctree::packGpuImage()):
 *   header  uint words: origin xyz and cells per unit (float bits), depth,
 *           start depth, layer count, unused, then 16 words per layer;
 *   offsets offset tables (x | y << 8 | z << 16);
 *   desc    description slots (uint2), data  light-data slots (uint4);
 *   list    index list entries, light | octant mask << 24.
 * hs_list_for() returns the entry range [offset, end) and the point's octant
 * bit; hs_next() yields entries whose mask has that bit. Include it; it has
 * no kernels. */
#ifndef HASHED_LOOKUP_CL
#define HASHED_LOOKUP_CL

typedef struct HsList {
  uint offset, end, octant_bit;
} HsList;

typedef struct HsBuffers {
  __global const uint* header;
  __global const uint* offsets;
  __global const uint2* desc;
  __global const uint4* data;
  __global const uint* list;
} HsBuffers;

inline uint4 hs_table(const HsBuffers* b, uint i) { return vload4(0, b->header + 8u + 4u * i); }

/* h(p) = (p mod m + Phi[p mod r]) mod m, flattened, plus the table's base. */
inline uint hs_slot(const HsBuffers* b, uint3 p, uint4 m, uint4 r) {
  const uint3 o = p % r.xyz;
  const uint phi = b->offsets[r.w + o.x + r.x * (o.y + r.y * o.z)];
  const uint3 off = (uint3)(phi & 0xFFu, (phi >> 8) & 0xFFu, (phi >> 16) & 0xFFu);
  const uint3 h = (p % m.xyz + off) % m.xyz;
  return m.w + h.x + m.x * (h.y + m.y * h.z);
}

inline HsList hs_list_for(const HsBuffers* b, float3 world) {
  HsList none = {0u, 0u, 0u};
  const float3 origin = (float3)(as_float(b->header[0]), as_float(b->header[1]), as_float(b->header[2]));
  const float3 q = (world - origin) * as_float(b->header[3]);
  const uint depth = b->header[4], start = b->header[5], layers = b->header[6];
  const float n = (float)(1u << depth);
  if (!(q.x >= 0.0f && q.y >= 0.0f && q.z >= 0.0f && q.x < n && q.y < n && q.z < n)) return none;
  const uint3 cell = min(convert_uint3(q), (uint3)((1u << depth) - 1u));
  for (uint i = 0u; i < layers; ++i) {
    const uint d = start + i;
    const uint3 cur = cell >> (depth - d);
    const uint3 nxt = cell >> (depth - d - 1u);
    const uint2 e = b->desc[hs_slot(b, cur, hs_table(b, 4u * i), hs_table(b, 4u * i + 1u))];
    if (e.x != (cur.x | (cur.y << 16)) || (e.y & 0xFFFFu) != cur.z) return none; /* no node: no lights */
    const uint3 k = nxt & 1u;
    const uint bit = k.x + 2u * k.y + 4u * k.z;
    if (((e.y >> (16u + bit)) & 1u) != 0u) {   /* the child is a leaf */
      if (((e.y >> (24u + bit)) & 1u) != 0u) { /* ... with lights */
        const uint4 dt = b->data[hs_slot(b, nxt, hs_table(b, 4u * i + 2u), hs_table(b, 4u * i + 3u))];
        if (dt.x == (nxt.x | (nxt.y << 16)) && (dt.y & 0xFFFFu) == nxt.z) {
          const uint3 h = convert_uint3(q * 2.0f) & 1u; /* the octant (exact: doubling is exact) */
          HsList l = {dt.z, dt.z + dt.w, 1u << (24u + h.x + 2u * h.y + 4u * h.z)};
          return l;
        }
      }
      return none;
    }
  }
  return none;
}

/* The next entry of `l`; false at the end and for an entry whose light does
 * not reach the point's octant (the caller skips it). */
inline bool hs_next(const HsBuffers* b, HsList* l, uint* light) {
  *light = 0u;
  if (l->offset >= l->end) return false;
  const uint e = b->list[l->offset++];
  *light = e & 0xFFFFFFu;
  return (e & l->octant_bit) != 0u;
}

#endif
