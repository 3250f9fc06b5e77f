/* Many independent segments of uint keys (uint values alongside when
 * has_values) sorted in one launch, a bitonic network per segment (see
 * prim_bitonic_network.cl). Segment s is [offsets[s], offsets[s + 1]) (clamped to n)
 * when use_offsets, else [s * seg_size, (s + 1) * seg_size) clamped to n.
 * CPU: work-item g sorts segments [g * segs_per_item, (g + 1) * segs_per_item)
 * in place; a segment is small and stays in cache. GPU: work-group s sorts
 * segment s, in local memory when it fits SEG_LOCAL elements, else in place in
 * global memory (the same network, global-memory barriers) so that no segment
 * size is refused. Both shapes take the same arguments; the last one is
 * segs_per_item on CPUs and max_np on GPUs (see below). */
#include "compute/prim_bitonic_network.cl"

/* Segment s as [begin, end); two functions rather than out-parameters so
 * that the work-group kernel keeps no private variable whose address is
 * taken live across barriers. */
ML_INLINE uint segment_end(uint s, uint n, __global const uint* offsets, uint use_offsets, uint seg_size) {
  return use_offsets ? min(offsets[s + 1], n) : chunk_begin(s + 1, seg_size, n);
}

ML_INLINE uint segment_begin(uint s, uint n, __global const uint* offsets, uint use_offsets, uint seg_size) {
  return use_offsets ? min(offsets[s], segment_end(s, n, offsets, use_offsets, seg_size))
                     : chunk_begin(s, seg_size, n);
}

#if !ML_GPU

__kernel void segmented_sort(__global uint* keys, __global uint* vals, uint has_values, uint n,
                             __global const uint* offsets, uint use_offsets, uint seg_size, uint nseg,
                             uint segs_per_item) {
  const uint g = get_global_id(0);
  const uint s0 = chunk_begin(g, segs_per_item, nseg), s1 = chunk_begin(g + 1, segs_per_item, nseg);
  for (uint s = s0; s < s1; ++s) {
    const uint b = segment_begin(s, n, offsets, use_offsets, seg_size);
    const uint e = segment_end(s, n, offsets, use_offsets, seg_size);
    if (has_values)
      bitonic_sort_range(keys + b, vals + b, 1, e - b);
    else
      bitonic_sort_range(keys + b, vals, 0, e - b);
  }
}

#else /* GPU */

/* Every barrier sits in a loop whose trip count comes from kernel arguments
 * (max_np) and never under a data-dependent branch: work-group uniform but
 * data-dependent barrier control flow is legal OpenCL, yet PoCL's work-item
 * loop construction ("peeling" of conditional barriers) miscompiles it
 * (observed: a later `for (i = lid; i < len; i += WG)` loop ran for every
 * work-item). So the stage loops run to max_np, a power of two >= every
 * segment length (next_pow2(seg_size) in fixed mode; with offsets next_pow2
 * of the host's stated bound, e.g. a tile's pixel count, else of n), and a
 * segment skips the stages beyond its own size. A segment longer than max_np
 * (a host bug) is sorted only in runs of max_np, never written outside. */
__kernel WG_ATTR void segmented_sort(__global uint* keys, __global uint* vals, uint has_values, uint n,
                                     __global const uint* offsets, uint use_offsets, uint seg_size, uint nseg,
                                     uint max_np) {
  __local uint lk[SEG_LOCAL], lv[SEG_LOCAL];
  const uint lid = get_local_id(0);
  const int hv = has_values != 0;
  const uint s = get_group_id(0);
  const uint b = segment_begin(s, n, offsets, use_offsets, seg_size);
  const uint len = segment_end(s, n, offsets, use_offsets, seg_size) - b;
  const uint np = next_pow2_u(len);
  /* Short segments are sorted in local memory (padded with maximum keys),
   * long ones in place in global memory with the same network. */
  const int in_local = np <= SEG_LOCAL;
  __global uint* k = keys + b;
  __global uint* v = vals + (hv ? b : 0);
  if (in_local) {
    for (uint i = lid; i < np; i += WG) {
      lk[i] = i < len ? k[i] : UINT_MAX;
      if (hv) lv[i] = i < len ? v[i] : 0u;
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint size = 2; size <= max_np; size <<= 1) {
    for (uint h = size >> 1; h > 0; h >>= 1) {
      if (size <= np) {
        for (uint t = lid; t < np / 2; t += WG) {
          uint hi;
          const uint lo = stage_pair(t, h, h == size >> 1, &hi);
          if (in_local)
            lcx(lk, lv, hv, lo, hi);
          else if (hi < len)
            gcx(k, v, hv, lo, hi);
        }
      }
      barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    }
  }
  if (in_local) {
    for (uint i = lid; i < len; i += WG) {
      k[i] = lk[i];
      if (hv) v[i] = lv[i];
    }
  }
}

#endif
