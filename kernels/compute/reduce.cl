/* Reductions of T = uint / int / float (ELEM_KIND 0 / 1 / 2):
 *   reduce_chunks_{min,max,sum}: one partial per chunk (CPU) / group (GPU),
 *   reduce_final_{min,max,sum}:  one work-item / group combines the partials
 *                                into out[out_index] (identity when count == 0);
 *   seg_minmax:  min and max of every segment [offsets[s], offsets[s + 1]) or
 *                [s * seg_size, (s + 1) * seg_size) clamped to n;
 *   tile_minmax: min and max of every tile x tile block of a width x height
 *                row-major image (per-tile depth bounds of tiled shading).
 * Empty ranges give the identities: min = T_MAX, max = T_LOWEST, sum = 0. Sums
 * wrap for the integer types. Both shapes take the same arguments. */
#include "compute/prim_common.cl"

#if ELEM_KIND == 0
typedef uint T;
typedef uint4 T4;
#define T_MAX 0xFFFFFFFFu
#define T_LOWEST 0u
#elif ELEM_KIND == 1
typedef int T;
typedef int4 T4;
#define T_MAX INT_MAX
#define T_LOWEST INT_MIN
#else
typedef float T;
typedef float4 T4;
#define T_MAX INFINITY
#define T_LOWEST (-INFINITY)
#endif

#define OP_MIN 0
#define OP_MAX 1
#define OP_SUM 2

/* `op` is always a literal at the call sites, so these fold to one instruction. */
ML_INLINE T identity(int op) { return op == OP_MIN ? T_MAX : op == OP_MAX ? T_LOWEST : (T)0; }

ML_INLINE T combine(int op, T a, T b) {
  if (op == OP_MIN) return min(a, b);
  if (op == OP_MAX) return max(a, b);
#if ELEM_KIND == 1
  return as_int(as_uint(a) + as_uint(b)); /* defined wrap-around */
#else
  return a + b;
#endif
}

ML_INLINE T4 combine4(int op, T4 a, T4 b) {
  if (op == OP_MIN) return min(a, b);
  if (op == OP_MAX) return max(a, b);
#if ELEM_KIND == 1
  return as_int4(as_uint4(a) + as_uint4(b));
#else
  return a + b;
#endif
}

ML_INLINE T combine_lanes(int op, T4 v) { return combine(op, combine(op, v.x, v.y), combine(op, v.z, v.w)); }

#if !ML_GPU

/* Two 4-wide accumulators: independent chains, and float sums in a tree-ish
 * order that loses less precision than one serial chain. */
ML_INLINE T reduce_range(int op, __global const T* restrict in, uint b, uint e) {
  T4 a0 = (T4)(identity(op)), a1 = a0;
  uint i = b;
  for (; i + 8 <= e; i += 8) {
    a0 = combine4(op, a0, vload4(0, in + i));
    a1 = combine4(op, a1, vload4(1, in + i));
  }
  T r = combine_lanes(op, combine4(op, a0, a1));
  for (; i < e; ++i) r = combine(op, r, in[i]);
  return r;
}

ML_INLINE void minmax_range(__global const T* restrict in, uint b, uint e, T* mn, T* mx) {
  T4 lo = (T4)(T_MAX), hi = (T4)(T_LOWEST);
  uint i = b;
  for (; i + 4 <= e; i += 4) {
    const T4 v = vload4(0, in + i);
    lo = min(lo, v);
    hi = max(hi, v);
  }
  T l = combine_lanes(OP_MIN, lo), h = combine_lanes(OP_MAX, hi);
  for (; i < e; ++i) {
    l = min(l, in[i]);
    h = max(h, in[i]);
  }
  *mn = min(*mn, l);
  *mx = max(*mx, h);
}

#define REDUCE_KERNELS(NAME, OP)                                                                            \
  __kernel void reduce_chunks_##NAME(__global const T* restrict in, uint n, uint chunk,                     \
                                     __global T* restrict partials) {                                       \
    const uint g = get_global_id(0);                                                                        \
    partials[g] = reduce_range(OP, in, chunk_begin(g, chunk, n), chunk_begin(g + 1, chunk, n));             \
  }                                                                                                         \
  __kernel void reduce_final_##NAME(__global const T* restrict partials, uint count, __global T* restrict out, \
                                    uint out_index) {                                                       \
    out[out_index] = reduce_range(OP, partials, 0, count);                                                  \
  }
REDUCE_KERNELS(min, OP_MIN)
REDUCE_KERNELS(max, OP_MAX)
REDUCE_KERNELS(sum, OP_SUM)

/* Work-item g owns segments [g * segs_per_item, (g + 1) * segs_per_item). */
__kernel void seg_minmax(__global const T* restrict in, uint n, __global const uint* restrict offsets,
                         uint use_offsets, uint seg_size, uint nseg, uint segs_per_item,
                         __global T* restrict out_min, __global T* restrict out_max) {
  const uint g = get_global_id(0);
  const uint s0 = chunk_begin(g, segs_per_item, nseg), s1 = chunk_begin(g + 1, segs_per_item, nseg);
  for (uint s = s0; s < s1; ++s) {
    uint b, e;
    if (use_offsets) {
      /* Clamped so that bad offsets cannot read out of bounds. */
      e = min(offsets[s + 1], n);
      b = min(offsets[s], e);
    } else {
      b = chunk_begin(s, seg_size, n);
      e = chunk_begin(s + 1, seg_size, n);
    }
    T mn = T_MAX, mx = T_LOWEST;
    minmax_range(in, b, e, &mn, &mx);
    out_min[s] = mn;
    out_max[s] = mx;
  }
}

/* Work-item g owns one row of tiles (or part of one: cols_per_item tiles) and
 * walks its image rows in memory order; the running bounds stay in the output
 * arrays, which are cache-resident. */
__kernel void tile_minmax(__global const T* restrict image, uint width, uint height, uint tile, uint tiles_x,
                          uint tiles_y, uint cols_per_item, __global T* restrict out_min,
                          __global T* restrict out_max) {
  const uint g = get_global_id(0);
  const uint blocks_x = (tiles_x + cols_per_item - 1) / cols_per_item;
  const uint ty = g / blocks_x, tx0 = (g % blocks_x) * cols_per_item;
  if (ty >= tiles_y) return;
  const uint tx1 = min(tiles_x, tx0 + cols_per_item);
  for (uint tx = tx0; tx < tx1; ++tx) {
    out_min[ty * tiles_x + tx] = T_MAX;
    out_max[ty * tiles_x + tx] = T_LOWEST;
  }
  const uint y1 = min(height, (ty + 1) * tile);
  for (uint y = ty * tile; y < y1; ++y) {
    __global const T* row = image + (size_t)y * width;
    for (uint tx = tx0; tx < tx1; ++tx) {
      T mn = out_min[ty * tiles_x + tx], mx = out_max[ty * tiles_x + tx];
      minmax_range(row, tx * tile, min(width, (tx + 1) * tile), &mn, &mx);
      out_min[ty * tiles_x + tx] = mn;
      out_max[ty * tiles_x + tx] = mx;
    }
  }
}

#else /* GPU: work-groups with local-memory tree reductions */

/* Tree reduction of one value per work-item; every work-item gets the result. */
ML_INLINE T wg_reduce(int op, T v, __local T* tmp) {
  const uint lid = get_local_id(0);
  tmp[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint s = WG / 2; s > 0; s >>= 1) {
    if (lid < s) tmp[lid] = combine(op, tmp[lid], tmp[lid + s]);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const T r = tmp[0];
  barrier(CLK_LOCAL_MEM_FENCE); /* tmp is reused by the caller's next call */
  return r;
}

ML_INLINE T wg_reduce_range(int op, __global const T* in, uint b, uint e, __local T* tmp) {
  T acc = identity(op);
  for (uint i = b + get_local_id(0); i < e; i += WG) acc = combine(op, acc, in[i]); /* coalesced */
  return wg_reduce(op, acc, tmp);
}

#define REDUCE_KERNELS(NAME, OP)                                                                              \
  __kernel WG_ATTR void reduce_chunks_##NAME(__global const T* in, uint n, uint chunk, __global T* partials) { \
    __local T tmp[WG];                                                                                        \
    const uint g = get_group_id(0);                                                                           \
    const T r = wg_reduce_range(OP, in, chunk_begin(g, chunk, n), chunk_begin(g + 1, chunk, n), tmp);         \
    if (get_local_id(0) == 0) partials[g] = r;                                                                \
  }                                                                                                           \
  __kernel WG_ATTR void reduce_final_##NAME(__global const T* partials, uint count, __global T* out,           \
                                            uint out_index) {                                                 \
    __local T tmp[WG];                                                                                        \
    const T r = wg_reduce_range(OP, partials, 0, count, tmp);                                                 \
    if (get_local_id(0) == 0) out[out_index] = r;                                                             \
  }
REDUCE_KERNELS(min, OP_MIN)
REDUCE_KERNELS(max, OP_MAX)
REDUCE_KERNELS(sum, OP_SUM)

/* Group s reduces segment s. */
__kernel WG_ATTR void seg_minmax(__global const T* in, uint n, __global const uint* offsets, uint use_offsets,
                                 uint seg_size, uint nseg, uint segs_per_item, __global T* out_min,
                                 __global T* out_max) {
  __local T tmp[WG];
  const uint s = get_group_id(0);
  uint b, e;
  if (use_offsets) {
    e = min(offsets[s + 1], n);
    b = min(offsets[s], e);
  } else {
    b = chunk_begin(s, seg_size, n);
    e = chunk_begin(s + 1, seg_size, n);
  }
  const T mn = wg_reduce_range(OP_MIN, in, b, e, tmp);
  const T mx = wg_reduce_range(OP_MAX, in, b, e, tmp);
  if (get_local_id(0) == 0) {
    out_min[s] = mn;
    out_max[s] = mx;
  }
}

/* Group t reduces tile t (row-major over tiles_x x tiles_y). */
__kernel WG_ATTR void tile_minmax(__global const T* image, uint width, uint height, uint tile, uint tiles_x,
                                  uint tiles_y, uint cols_per_item, __global T* out_min, __global T* out_max) {
  __local T tmp[WG];
  const uint t = get_group_id(0);
  /* Quotient and remainder without `%`: LLVM pairs x / y with x % y into a
   * `freeze` instruction that Oclgrind cannot simulate (scripts/oclgrind.sh). */
  const uint ty = t / tiles_x, tx = t - ty * tiles_x;
  const uint x0 = tx * tile, y0 = ty * tile;
  const uint tw = min(width, x0 + tile) - x0, th = min(height, y0 + tile) - y0;
  T mn = T_MAX, mx = T_LOWEST;
  for (uint i = get_local_id(0); i < tw * th; i += WG) {
    const uint row = i / tw;
    const T v = image[(size_t)(y0 + row) * width + x0 + (i - row * tw)];
    mn = min(mn, v);
    mx = max(mx, v);
  }
  mn = wg_reduce(OP_MIN, mn, tmp);
  mx = wg_reduce(OP_MAX, mx, tmp);
  if (get_local_id(0) == 0) {
    out_min[t] = mn;
    out_max[t] = mx;
  }
}

#endif
