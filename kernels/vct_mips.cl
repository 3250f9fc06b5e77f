/* Voxel mip propagation (voxel cone tracing); parent voxel p of a level with
 * edge ep = 1 << ep_log2 has children 2x..2x+1, 2y..2y+1, 2z..2z+1 at the
 * finer level (edge 2ep). Layout of both volumes: host/shared/voxel_types.h.
 *   mip_iso:   per axis, each of the 4 child pairs along it composited front
 *              to back (front + (1 - front.a) * back, premultiplied) in both
 *              orders and averaged, the 4 columns averaged; the parent is the
 *              axis with the largest opacity. A wall filling one of the two
 *              child layers stays opaque across it (the mean of the 8
 *              children, 002's filter, halves its opacity per level and cones
 *              leak through one-voxel walls). Opacity stays separate from
 *              colour: an opaque black child adds opacity, an empty one not.
 *   mip_aniso: per direction of travel d (+X, -X, +Y, -Y, +Z, -Z), each of
 *              the 4 child pairs along d's axis composited front to back
 *              (front + (1 - front.a) * back), then the 4 results averaged
 *              (Crassin 2011). Children: direction d of the finer anisotropic
 *              level, or, for level 1, isotropic level 0.
 * One launch fills levels l0 + 1 .. l0 + depth (MIP_TREE): each top parent
 * owns its subtree, so small grids are not launch-bound. Shapes
 * (vct_common.cl): ML_GPU=0 walks a range of top parents per work-item
 * (local size 1); ML_GPU=1 runs one work-group per top parent. Every child is
 * read once per parent and value set (anisotropic level 1: once for all six
 * directions), so local memory would save nothing.
 * FP_CONTRACT is off so the sums and composites round as in the C++ twin
 * (host/vct/VoxelMipsReference.hpp), which the tests compare bit for bit. */
#pragma OPENCL FP_CONTRACT OFF
#include "vct_common.cl"
#include "gpu_types.h"
#include "voxel_types.h"

/* The index of parent p's child (0, 0, 0) in the finer level. */
ML_INLINE uint child_base(uint p, uint ep_log2) {
  const uint mask = (1u << ep_log2) - 1u;
  const uint x = p & mask, y = (p >> ep_log2) & mask, z = p >> (2u * ep_log2);
  const uint ec = 2u << ep_log2;
  return 2u * x + ec * (2u * y + ec * 2u * z);
}

ML_INLINE float4 over(float4 front, float4 back) { return front + (1.0f - front.w) * back; }

/* A parent's 8 children, k[x + 2y + 4z]. */
ML_INLINE void load8(__global const float4* c, uint sy, uint sz, float4* k) {
  k[0] = c[0];
  k[1] = c[1];
  k[2] = c[sy];
  k[3] = c[sy + 1];
  k[4] = c[sz];
  k[5] = c[sz + 1];
  k[6] = c[sz + sy];
  k[7] = c[sz + sy + 1];
}

/* Direction d of one parent: the 4 pairs along d's axis (bit s of the child
 * index), u and v the other two axes' bits, in the twin's order. */
ML_INLINE float4 aniso_dir(const float4* k, uint d) {
  const uint axis = d >> 1;
  const uint s = 1u << axis;
  const uint u = axis == 0 ? 2u : 1u;
  const uint v = axis == 2 ? 2u : 4u;
  const uint f = (d & 1u) ? s : 0u; /* -axis travel meets the high child first */
  const uint b = s - f;
  const float4 p0 = over(k[f], k[b]);
  const float4 p1 = over(k[u + f], k[u + b]);
  const float4 p2 = over(k[v + f], k[v + b]);
  const float4 p3 = over(k[u + v + f], k[u + v + b]);
  return ((p0 + p1) + (p2 + p3)) * 0.25f;
}

/* A 2x1x1 pair composited front to back in both orders and averaged (an
 * isotropic voxel has no direction of travel): (over(a, b) + over(b, a)) / 2
 * = (1 - b.a / 2) a + (1 - a.a / 2) b; opacity a0 + a1 - a0 a1 either way.
 * pair_alpha() is its opacity alone, the same operations as pair_iso()'s w. */
ML_INLINE float pair_alpha(float a, float b) { return (1.0f - 0.5f * b) * a + (1.0f - 0.5f * a) * b; }
ML_INLINE float4 pair_iso(float4 a, float4 b) { return (1.0f - 0.5f * b.w) * a + (1.0f - 0.5f * a.w) * b; }

/* The opacity of the 4 pairs along `axis` (bit s of the child index; u, v
 * the other two axes' bits), averaged, and the same for all four values. */
#define ISO_AXIS(pair, k, s, u, v) \
  (((pair(k[0], k[s]) + pair(k[u], k[u + s])) + (pair(k[v], k[v + s]) + pair(k[u + v], k[u + v + s]))) * 0.25f)

ML_INLINE float4 iso_axis(const float4* k, uint axis) {
  const uint s = 1u << axis, u = axis == 0 ? 2u : 1u, v = axis == 2 ? 2u : 4u;
  return ISO_AXIS(pair_iso, k, s, u, v);
}

/* One isotropic parent: the axis whose pairs are the most opaque (the first
 * on ties, x before y before z), its 4 composited pairs averaged. Opacities
 * first, so only the chosen axis pays for colour. Keeping the most opaque
 * axis, not the mean of the three, holds a one-voxel wall opaque at every
 * level (the mean gives 2/3, 4/9, ..): Cornell box, 64^3, 9 cones, 160x90,
 * rel RMSE 0.353 against 0.438 for the mean of the axes. */
ML_INLINE float4 iso_parent(__global const float4* c, uint sy, uint sz) {
  float4 k[8];
  load8(c, sy, sz, k);
  const float ka[8] = {k[0].w, k[1].w, k[2].w, k[3].w, k[4].w, k[5].w, k[6].w, k[7].w};
  const float ax = ISO_AXIS(pair_alpha, ka, 1u, 2u, 4u);
  const float ay = ISO_AXIS(pair_alpha, ka, 2u, 1u, 4u);
  const float az = ISO_AXIS(pair_alpha, ka, 4u, 1u, 2u);
  const uint axis = az > max(ax, ay) ? 2u : (ay > ax ? 1u : 0u);
  return iso_axis(k, axis);
}

/* Parent i (0 .. 8^m_log2 - 1, x fastest) of the block of 2^m_log2 parents
 * per axis under top parent t, in a level of edge 1 << (et_log2 + m_log2)
 * (et: the top level's edge). */
ML_INLINE uint block_parent(uint t, uint et_log2, uint i, uint m_log2) {
  const uint tm = (1u << et_log2) - 1u, im = (1u << m_log2) - 1u, e_log2 = et_log2 + m_log2;
  const uint x = ((t & tm) << m_log2) | (i & im);
  const uint y = (((t >> et_log2) & tm) << m_log2) | ((i >> m_log2) & im);
  const uint z = ((t >> (2u * et_log2)) << m_log2) | (i >> (2u * m_log2));
  return x + (y << e_log2) + (z << (2u * e_log2));
}

/* Parent i of level l's block under top parent t (level lt): isotropic, in
 * place in the all-levels volume. */
ML_INLINE void iso_one(__global float4* vol, uint edge_log2, uint l, uint lt, uint t, uint i) {
  const uint edge = 1u << edge_log2, m_log2 = lt - l, et_log2 = edge_log2 - lt, ep_log2 = et_log2 + m_log2;
  const uint ec = 2u << ep_log2, p = block_parent(t, et_log2, i, m_log2);
  vol[voxel_level_offset(edge, l) + p] = iso_parent(vol + voxel_level_offset(edge, l - 1u) + child_base(p, ep_log2), ec, ec * ec);
}

/* The same for the anisotropic volume: level 1 reads isotropic level 0 of
 * `radiance` once for all six directions, levels >= 2 direction d of the
 * finer anisotropic level. */
ML_INLINE void aniso_one(__global const float4* radiance, __global float4* aniso, uint edge_log2, uint l, uint lt,
                         uint t, uint i) {
  const uint edge = 1u << edge_log2, m_log2 = lt - l, et_log2 = edge_log2 - lt, ep_log2 = et_log2 + m_log2;
  const uint ec = 2u << ep_log2, p = block_parent(t, et_log2, i, m_log2), n = 1u << (3u * ep_log2);
  const bool from_iso = l == 1u;
  __global const float4* c =
      (from_iso ? radiance : aniso + voxel_aniso_index(edge, l - 1u, 0u, 0u)) + child_base(p, ep_log2);
  __global float4* dst = aniso + voxel_aniso_index(edge, l, 0u, p);
  float4 k[8];
  if (from_iso) load8(c, ec, ec * ec, k);
#pragma unroll
  for (uint d = 0; d < 6u; ++d) {
    if (!from_iso) load8(c + d * 8u * n, ec, ec * ec, k);
    dst[d * n] = aniso_dir(k, d);
  }
}

/* Levels l0 + 1 .. l0 + depth in one launch: each top parent (level
 * lt = l0 + depth, n_top of them) owns the subtree below it down to level
 * l0, so no level waits for another work-item. ML_GPU=0: a work-item walks
 * a range of top parents, every level of each in turn (the subtree stays in
 * cache); ML_GPU=1: a work-group takes `tops` consecutive top parents
 * (WG / 64: the first level's blocks of 4^3 fill it), its work-items
 * striding over a level's parents, a barrier between levels (global fence:
 * the next level reads them). */
#if ML_GPU
#define MIP_TREE(one_call)                                                    \
  for (uint l = l0 + 1u; l <= l0 + depth; ++l) {                              \
    const uint m3 = 3u * (l0 + depth - l);                                    \
    for (uint j = get_local_id(0); j < (tops << m3); j += WG) {               \
      const uint t = get_group_id(0) * tops + (j >> m3);                      \
      if (t < n_top) one_call(l, t, j & ((1u << m3) - 1u));                   \
    }                                                                         \
    barrier(CLK_GLOBAL_MEM_FENCE);                                            \
  }
#else
#define MIP_TREE(one_call)                                                    \
  uint b, e;                                                                  \
  item_range(n_top, tops, &b, &e);                                            \
  for (uint t = b; t < e; ++t)                                                \
    for (uint l = l0 + 1u; l <= l0 + depth; ++l)                              \
      for (uint i = 0; i < (1u << (3u * (l0 + depth - l))); ++i) one_call(l, t, i);
#endif

/* `tops`: top parents per work-item (ML_GPU=0) or work-group (ML_GPU=1). */
__kernel VCT_ATTR void mip_iso(__global float4* vol, uint edge_log2, uint l0, uint depth, uint n_top, uint tops) {
#define ISO_CALL(l, t, i) iso_one(vol, edge_log2, l, l0 + depth, t, i)
  MIP_TREE(ISO_CALL)
#undef ISO_CALL
}

__kernel VCT_ATTR void mip_aniso(__global const float4* radiance, __global float4* aniso, uint edge_log2, uint l0,
                                 uint depth, uint n_top, uint tops) {
#define ANISO_CALL(l, t, i) aniso_one(radiance, aniso, edge_log2, l, l0 + depth, t, i)
  MIP_TREE(ANISO_CALL)
#undef ANISO_CALL
}
