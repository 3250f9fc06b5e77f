/* Voxel mip propagation (voxel cone tracing); parent voxel p of a level with
 * edge ep = 1 << ep_log2 has children 2x..2x+1, 2y..2y+1, 2z..2z+1 at the
 * finer level (edge 2ep). Layout of both volumes: host/shared/voxel_types.h.
 *   mip_iso:   per axis, each of the 4 child pairs along it composited front
 *              to back (front + (1 - front.a) * back, premultiplied) in the
 *              brighter of the two orders, the 4 columns averaged; the parent
 *              is the axis with the largest opacity. A wall filling one of the two
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
 * (vct_common.cl): ML_GPU=0, a work-item owns a range of top-level z-slices
 * (local size 1) and walks them row by row, 4 parents per float16
 * (iso_parent_quad, aniso_slices); ML_GPU=1, a work-group owns a set of top
 * parents, one parent per work-item. Every
 * child is read once per parent and value set (anisotropic level 1: once for
 * all six directions), so local memory would save nothing.
 * FP_CONTRACT is off so the sums and composites round as in the C++ twin
 * (host/vct/VoxelMipsReference.hpp), which the tests compare bit for bit. */
#pragma OPENCL FP_CONTRACT OFF
#include "vct/vct_common.cl"
#include "gpu_types.h"
#include "voxel_types.h"

/* The index of parent p's child (0, 0, 0) in the finer level. */
ML_INLINE uint child_base(uint p, uint ep_log2) {
  const uint mask = (1u << ep_log2) - 1u;
  const uint x = p & mask, y = (p >> ep_log2) & mask, z = p >> (2u * ep_log2);
  const uint ec = 2u << ep_log2;
  return 2u * x + ec * (2u * y + ec * 2u * z);
}

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

/* One axis of one parent, both directions of travel at once: lanes 0-3 the
 * + direction (children kp, the low child in front), lanes 4-7 the -
 * direction (children kn, the high child in front); each of the 4 pairs
 * along the axis (bit s of the child index; u, v the other two axes' bits)
 * composited front to back, then averaged, in the twin's order. */
ML_INLINE float8 over8(float8 f, float8 b) {
  const float8 fa = (float8)(f.s3, f.s3, f.s3, f.s3, f.s7, f.s7, f.s7, f.s7);
  return f + (1.0f - fa) * b;
}
/* Built from components, as over8()'s broadcast: Oclgrind 21.10
 * (scripts/oclgrind.sh) crashed on the kernel with the vector concatenation
 * (float8)(a, b); PoCL runs both forms at the same speed. */
ML_INLINE float8 cat8(float4 a, float4 b) { return (float8)(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w); }
#define ANISO_PAIR(kp, kn, i, s) over8(cat8(kp[i], kn[i + s]), cat8(kp[i + s], kn[i]))
#define ANISO_AXIS(kp, kn, s, u, v) \
  (((ANISO_PAIR(kp, kn, 0u, s) + ANISO_PAIR(kp, kn, u, s)) + (ANISO_PAIR(kp, kn, v, s) + ANISO_PAIR(kp, kn, u + v, s))) * 0.25f)

/* Isotropic filter. Along an axis, each of the 4 child pairs (f, b) is
 * composited front to back in both orders, over(f, b) = f + (1 - f.a) b and
 * over(b, f), and the brighter of the two kept (brighter(); their opacity
 * is the same, f.a + b.a - f.a b.a); the axis is the mean of its 4 pairs
 * (AXIS_MAX / 4). An isotropic voxel has no direction of travel, and the
 * mean of the two orders, as before, gave a wall's lit face and its dark
 * back (a slab two children thick) half the light from every side: the
 * lit face is what the open space around a surface sees, the back faces
 * into the wall. Cornell box, its camera, 320x320, 9 cones, isotropic,
 * against a 1024-sample reference without its noise, 32^3 / 64^3 / 128^3:
 * 0.181 / 0.185 / 0.215 (the mean: 0.231 / 0.265 / 0.236; a channel-wise
 * max 0.181 / 0.186 / 0.217; anisotropic 0.165 / 0.160 / 0.143).
 * The parent is the most opaque axis: the one whose pairs overlap least,
 * sum f.a b.a (AXIS_OVERLAP), the first on ties (x, y, z). Pairs as child
 * indices (f0, b0, ..), in the twin's order. */
#define PAIR_OVERLAP(A, i, j) (A(i) * A(j))
#define AXIS_OVERLAP(A, f0, b0, f1, b1, f2, b2, f3, b3) \
  ((PAIR_OVERLAP(A, f0, b0) + PAIR_OVERLAP(A, f1, b1)) + (PAIR_OVERLAP(A, f2, b2) + PAIR_OVERLAP(A, f3, b3)))
/* The brighter of the pair's two orders, whole (a channel-wise max would
 * make an opaque red and green pair yellow): over(i, j) - over(j, i) =
 * A(j) k[i] - A(i) k[j], so over(i, j) is at least as bright (rgb summed,
 * S(i) = (r + g) + b of child i) when A(j) S(i) >= A(i) S(j); ties, over(i, j).
 * PICK(l, r, x, y): x where l >= r, else y (a scalar ?:, or select() per lane). */
#define OVER_PAIR(A, i, j) (k[i] + (1.0f - A(i)) * k[j])
#define PAIR_MAX(A, S, PICK, i, j) PICK(A(j) * S(i), A(i) * S(j), OVER_PAIR(A, i, j), OVER_PAIR(A, j, i))
#define AXIS_MAX(A, S, PICK, f0, b0, f1, b1, f2, b2, f3, b3)                                                  \
  ((PAIR_MAX(A, S, PICK, f0, b0) + PAIR_MAX(A, S, PICK, f1, b1)) +                                           \
   (PAIR_MAX(A, S, PICK, f2, b2) + PAIR_MAX(A, S, PICK, f3, b3)))
#define PICK1(l, r, x, y) ((l) >= (r) ? (x) : (y))
#define RGB_SUM(i) s[i]
/* The pairs (f0, b0, ..) of each axis, as child indices in the twin's order;
 * OVERLAP(A, X_PAIRS) etc. expand the list before AXIS_OVERLAP sees it. A(i):
 * child i's opacity, a scalar (k[i].w) or broadcast over its lanes. */
#define X_PAIRS 0, 1, 2, 3, 4, 5, 6, 7
#define Y_PAIRS 0, 2, 1, 3, 4, 6, 5, 7
#define Z_PAIRS 0, 4, 1, 5, 2, 6, 3, 7
#define OVERLAP(...) AXIS_OVERLAP(__VA_ARGS__)
#define BRIGHTER(...) AXIS_MAX(__VA_ARGS__)
#define ALPHA(i) k[i].w

/* Keeping the most opaque axis, not the mean of the three, holds a one-voxel
 * wall opaque at every level (the mean gives 2/3, 4/9, ..): Cornell box,
 * 64^3, 9 cones, 160x90, rel RMSE 0.353 against 0.438 for the mean. */
ML_INLINE float4 iso_parent(__global const float4* c, uint sy, uint sz) {
  float4 k[8];
  load8(c, sy, sz, k);
  float s[8];
  for (uint i = 0u; i < 8u; ++i) s[i] = (k[i].x + k[i].y) + k[i].z;
  const float dx = OVERLAP(ALPHA, X_PAIRS), dy = OVERLAP(ALPHA, Y_PAIRS), dz = OVERLAP(ALPHA, Z_PAIRS);
  if (dz < min(dx, dy)) return BRIGHTER(ALPHA, RGB_SUM, PICK1, Z_PAIRS) * 0.25f;
  if (dy < dx) return BRIGHTER(ALPHA, RGB_SUM, PICK1, Y_PAIRS) * 0.25f;
  return BRIGHTER(ALPHA, RGB_SUM, PICK1, X_PAIRS) * 0.25f;
}

#if !ML_GPU
/* CPU shape: 4 x-adjacent parents at once, parent j in float4 lane group j
 * of each float16. Their children are two rows of 8 float4 per (y, z) child
 * pair, contiguous, so k[i] (child i of the 4 parents) is a shuffle of two
 * row loads, and the 4 results are one contiguous store. Every float16
 * operation does the work of 4 float4 ones (the filter is bound by
 * instructions: 002's box filter ran at the copy kernel's speed). The axis
 * choice is per lane group: select() over the three axes' pairs, and only the
 * x ones when no parent picks another (ties go to x: every empty or uniform
 * block), where a branch per parent mispredicts on mixed volumes. Each lane
 * group rounds exactly as iso_parent(). */
#define W16(v)                                                                                                  \
  ((float16)((v).s3, (v).s3, (v).s3, (v).s3, (v).s7, (v).s7, (v).s7, (v).s7, (v).sb, (v).sb, (v).sb, (v).sb, \
             (v).sf, (v).sf, (v).sf, (v).sf))
#define ALPHA16(i) w[i]
/* The even and odd children (float4 0, 2, 4, 6 and 1, 3, 5, 7) of a row of 8
 * loaded as two float16, component by component: Oclgrind 21.10 crashed on
 * the kernel joining float4 swizzles, and PoCL ran this form faster. */
#define EVEN_CHILDREN(a, b)                                                                                          \
  ((float16)((a).s0, (a).s1, (a).s2, (a).s3, (a).s8, (a).s9, (a).sa, (a).sb, (b).s0, (b).s1, (b).s2, (b).s3, (b).s8, \
             (b).s9, (b).sa, (b).sb))
#define ODD_CHILDREN(a, b)                                                                                           \
  ((float16)((a).s4, (a).s5, (a).s6, (a).s7, (a).sc, (a).sd, (a).se, (a).sf, (b).s4, (b).s5, (b).s6, (b).s7, (b).sc, \
             (b).sd, (b).se, (b).sf))
/* A lane of each parent: any() over int16 compiled to a slow lane loop. */
#define ANY_PARENT(m) (((m).s0 | (m).s4) | ((m).s8 | (m).sc))
/* k[i]: child i of the 4 parents whose first child is c[0]. */
ML_INLINE void load_quad(__global const float4* c, uint sy, uint sz, float16* k) {
  for (uint r = 0u; r < 4u; ++r) {
    __global const float* row = (__global const float*)(c + (r & 1u) * sy + (r >> 1u) * sz);
    const float16 a = vload16(0u, row), b = vload16(1u, row);
    k[2u * r] = EVEN_CHILDREN(a, b);
    k[2u * r + 1u] = ODD_CHILDREN(a, b);
  }
}
/* Each lane group's (r + g) + b, broadcast over its lanes (as W16 does the opacity). */
#define RGB16(v)                                                                                    \
  ((float16)(RGB16_GROUP(v, s0, s1, s2), RGB16_GROUP(v, s4, s5, s6), RGB16_GROUP(v, s8, s9, sa), \
             RGB16_GROUP(v, sc, sd, se)))
#define RGB16_GROUP(v, r, g, b) ((v).r + (v).g) + (v).b, ((v).r + (v).g) + (v).b, ((v).r + (v).g) + (v).b, \
                                ((v).r + (v).g) + (v).b
#define PICK16(l, r, x, y) select((y), (x), isgreaterequal((l), (r)))
ML_INLINE void iso_parent_quad(__global const float4* c, uint sy, uint sz, __global float4* dst) {
  float16 k[8], w[8], s[8];
  load_quad(c, sy, sz, k);
  for (uint i = 0u; i < 8u; ++i) {
    w[i] = W16(k[i]);
    s[i] = RGB16(k[i]);
  }
  const float16 dx = OVERLAP(ALPHA16, X_PAIRS), dy = OVERLAP(ALPHA16, Y_PAIRS), dz = OVERLAP(ALPHA16, Z_PAIRS);
  const int16 use_y = isless(dy, dx), use_z = isless(dz, fmin(dx, dy));
  float16 axis = BRIGHTER(ALPHA16, RGB_SUM, PICK16, X_PAIRS);
  if ((ANY_PARENT(use_y) | ANY_PARENT(use_z)) != 0)
    axis = select(select(axis, BRIGHTER(ALPHA16, RGB_SUM, PICK16, Y_PAIRS), use_y),
                  BRIGHTER(ALPHA16, RGB_SUM, PICK16, Z_PAIRS), use_z);
  vstore16(axis * 0.25f, 0u, (__global float*)dst);
}

/* Level l's parents in z-slices z0 .. z1 - 1, row by row: level offsets once
 * per level and row starts once per row, not per parent. Edges are powers of
 * two, so rows of >= 4 parents split into quads; smaller levels are tiny. */
ML_INLINE void iso_slices(__global float4* vol, uint edge_log2, uint l, uint z0, uint z1) {
  const uint edge = 1u << edge_log2, ep = edge >> l, ec = 2u * ep;
  __global const float4* child = vol + voxel_level_offset(edge, l - 1u);
  __global float4* parent = vol + voxel_level_offset(edge, l);
  for (uint z = z0; z < z1; ++z)
    for (uint y = 0u; y < ep; ++y) {
      __global const float4* c = child + 2u * ec * (y + ec * z);
      __global float4* d = parent + ep * (y + ep * z);
      if (ep >= 4u)
        for (uint x = 0u; x < ep; x += 4u) iso_parent_quad(c + 2u * x, ec, ec * ec, d + x);
      else
        for (uint x = 0u; x < ep; ++x) d[x] = iso_parent(c + 2u * x, ec, ec * ec);
    }
}
#endif

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

/* Parent p of level l (edge 1 << ep_log2): isotropic, in place in the
 * all-levels volume. */
ML_INLINE void iso_one(__global float4* vol, uint edge_log2, uint l, uint ep_log2, uint p) {
  const uint edge = 1u << edge_log2, ec = 2u << ep_log2;
  vol[voxel_level_offset(edge, l) + p] = iso_parent(vol + voxel_level_offset(edge, l - 1u) + child_base(p, ep_log2), ec, ec * ec);
}

/* The same for the anisotropic volume: level 1 reads isotropic level 0 of
 * `radiance` once for all six directions, levels >= 2 direction d of the
 * finer anisotropic level. */
ML_INLINE void aniso_one(__global const float4* radiance, __global float4* aniso, uint edge_log2, uint l, uint ep_log2,
                         uint p) {
  const uint edge = 1u << edge_log2, ec = 2u << ep_log2, n = 1u << (3u * ep_log2);
  const bool from_iso = l == 1u;
  __global const float4* c =
      (from_iso ? radiance : aniso + voxel_aniso_index(edge, l - 1u, 0u, 0u)) + child_base(p, ep_log2);
  __global float4* dst = aniso + voxel_aniso_index(edge, l, 0u, p);
  float4 kp[8], kn[8];
  float8 r;
#define ANISO_STORE(axis, s, u, v)                                      \
  if (!from_iso) {                                                      \
    load8(c + (2u * axis) * 8u * n, ec, ec * ec, kp);                   \
    load8(c + (2u * axis + 1u) * 8u * n, ec, ec * ec, kn);              \
  }                                                                     \
  r = from_iso ? ANISO_AXIS(kp, kp, s, u, v) : ANISO_AXIS(kp, kn, s, u, v); \
  dst[2u * axis * n] = r.lo;                                            \
  dst[(2u * axis + 1u) * n] = r.hi;
  if (from_iso) load8(c, ec, ec * ec, kp);
  ANISO_STORE(0u, 1u, 2u, 4u)
  ANISO_STORE(1u, 2u, 1u, 4u)
  ANISO_STORE(2u, 4u, 1u, 2u)
#undef ANISO_STORE
}

#if !ML_GPU
/* CPU shape, anisotropic: 4 x-adjacent parents per float16 as in
 * iso_parent_quad(); direction 2 axis + neg composites the pairs along the
 * axis (stride s; u, v the other two axes' strides) with the low child in
 * front (neg = 0) or the high one, in anisoDir()'s order. */
ML_INLINE float16 over16(float16 f, float16 b) { return f + (1.0f - W16(f)) * b; }
#define OVER_PAIR(i, s, neg) ((neg) ? over16(k[(i) + (s)], k[i]) : over16(k[i], k[(i) + (s)]))
ML_INLINE float16 aniso_quad_dir(const float16* k, uint s, uint u, uint v, bool neg) {
  return ((OVER_PAIR(0u, s, neg) + OVER_PAIR(u, s, neg)) + (OVER_PAIR(v, s, neg) + OVER_PAIR(u + v, s, neg))) * 0.25f;
}

/* Level l's parents in z-slices z0 .. z1 - 1, row by row as iso_slices():
 * level 1 loads isotropic level 0 once for all six directions, levels >= 2
 * direction d of the finer level; rows under 4 parents use aniso_one(). */
ML_INLINE void aniso_slices(__global const float4* radiance, __global float4* aniso, uint edge_log2, uint l, uint z0,
                            uint z1) {
  const uint edge = 1u << edge_log2, ep = edge >> l, ec = 2u * ep, n = ep * ep * ep, nc = 8u * n;
  const bool from_iso = l == 1u;
  __global const float4* src = from_iso ? radiance : aniso + voxel_aniso_index(edge, l - 1u, 0u, 0u);
  __global float4* dst = aniso + voxel_aniso_index(edge, l, 0u, 0u);
  float16 k[8];
#define ANISO_QUAD_AXIS(axis, s, u, v)                                                           \
  for (uint neg = 0u; neg < 2u; ++neg) {                                                         \
    const uint d = 2u * (axis) + neg;                                                            \
    if (!from_iso) load_quad(src + d * nc + c, ec, ec * ec, k);                                  \
    vstore16(aniso_quad_dir(k, s, u, v, neg != 0u), 0u, (__global float*)(dst + d * n + p)); \
  }
  for (uint z = z0; z < z1; ++z)
    for (uint y = 0u; y < ep; ++y)
      for (uint x = 0u; x < ep; x += ep >= 4u ? 4u : 1u) {
        const uint c = 2u * x + 2u * ec * (y + ec * z), p = x + ep * (y + ep * z);
        if (ep < 4u) {
          aniso_one(radiance, aniso, edge_log2, l, edge_log2 - l, p);
          continue;
        }
        if (from_iso) load_quad(src + c, ec, ec * ec, k);
        ANISO_QUAD_AXIS(0u, 1u, 2u, 4u)
        ANISO_QUAD_AXIS(1u, 2u, 1u, 4u)
        ANISO_QUAD_AXIS(2u, 4u, 1u, 2u)
      }
#undef ANISO_QUAD_AXIS
}
#endif

/* Levels l0 + 1 .. l0 + depth (= lt) in one launch: every parent below a top
 * parent (level lt) depends only on that top parent's subtree, so a
 * work-item or work-group that owns whole subtrees needs no other.
 * ML_GPU=0: a work-item owns `tops` z-slices of the top level (all their
 * subtrees); below them each level's parents are one contiguous range, walked
 * level after level in memory order (streams, as a per-level launch would).
 * ML_GPU=1: a work-group owns `tops` consecutive top parents (WG / 64: the
 * first level's blocks of 4^3 fill it), its work-items striding over a
 * level's parents, a barrier between levels (global fence: the next level
 * reads them). */
#if ML_GPU
#define MIP_TREE(one_call)                                                         \
  const uint lt = l0 + depth, et_log2 = edge_log2 - lt;                            \
  for (uint l = l0 + 1u; l <= lt; ++l) {                                           \
    const uint m_log2 = lt - l, m3 = 3u * m_log2;                                  \
    for (uint j = get_local_id(0); j < (tops << m3); j += WG) {                    \
      const uint t = get_group_id(0) * tops + (j >> m3);                           \
      if (t < (1u << (3u * et_log2)))                                              \
        one_call(l, et_log2 + m_log2, block_parent(t, et_log2, j & ((1u << m3) - 1u), m_log2)); \
    }                                                                              \
    barrier(CLK_GLOBAL_MEM_FENCE);                                                 \
  }
#else
#define MIP_TREE(one_call)                                                         \
  uint b, e;                                                                       \
  item_range(1u << (edge_log2 - l0 - depth), tops, &b, &e);                        \
  for (uint l = l0 + 1u; l <= l0 + depth; ++l) {                                   \
    const uint ep_log2 = edge_log2 - l, shift = (l0 + depth - l) + 2u * ep_log2;   \
    for (uint p = b << shift; p < (e << shift); ++p) one_call(l, ep_log2, p);      \
  }
#endif

/* `tops`: top-level z-slices per work-item (ML_GPU=0), top parents per
 * work-group (ML_GPU=1). */
__kernel VCT_ATTR void mip_iso(__global float4* vol, uint edge_log2, uint l0, uint depth, uint tops) {
#if ML_GPU
#define ISO_CALL(l, ep_log2, p) iso_one(vol, edge_log2, l, ep_log2, p)
  MIP_TREE(ISO_CALL)
#undef ISO_CALL
#else
  /* MIP_TREE's walk, row by row (iso_slices). */
  uint b, e;
  item_range(1u << (edge_log2 - l0 - depth), tops, &b, &e);
  for (uint l = l0 + 1u; l <= l0 + depth; ++l) {
    const uint m_log2 = l0 + depth - l;  // level l's z-slices per top-level one
    iso_slices(vol, edge_log2, l, b << m_log2, e << m_log2);
  }
#endif
}

__kernel VCT_ATTR void mip_aniso(__global const float4* radiance, __global float4* aniso, uint edge_log2, uint l0,
                                 uint depth, uint tops) {
#if ML_GPU
#define ANISO_CALL(l, ep_log2, p) aniso_one(radiance, aniso, edge_log2, l, ep_log2, p)
  MIP_TREE(ANISO_CALL)
#undef ANISO_CALL
#else
  uint b, e;
  item_range(1u << (edge_log2 - l0 - depth), tops, &b, &e);
  for (uint l = l0 + 1u; l <= l0 + depth; ++l) {
    const uint m_log2 = l0 + depth - l;
    aniso_slices(radiance, aniso, edge_log2, l, b << m_log2, e << m_log2);
  }
#endif
}
