/* Prefix sums of uint (wrapping), reduce-then-scan:
 *   scan_reduce: one partial sum per chunk (CPU) / tile (GPU),
 *   (the host scans the partials with the same kernels, recursively),
 *   scan_tiles:  scan each chunk / tile starting from its scanned partial.
 * No work-group ever waits on another, so the design is safe on any OpenCL
 * device. `in` and `out` may be the same buffer (in-place scan): each element
 * is read before it is written by the same work-item / work-group. Both shapes
 * take the same arguments; `chunk` is unused by the work-group shape, whose
 * group g owns tile g of WG * ITEMS elements. */
#include "compute/prim_common.cl"

#if ML_GPU
__kernel WG_ATTR void scan_reduce(__global const uint* in, __global uint* partials, uint n, uint chunk) {
  __local uint tmp[WG];
  const uint lid = get_local_id(0);
  const uint base = get_group_id(0) * TILE;
  uint s = 0;
  for (uint i = lid; i < TILE; i += WG) { /* strided: coalesced loads */
    const uint idx = base + i;
    if (idx < n) s += in[idx];
  }
  uint total;
  wg_exclusive_scan(s, tmp, &total);
  if (lid == 0) partials[get_group_id(0)] = total;
}

__kernel WG_ATTR void scan_tiles(__global const uint* in, __global uint* out, uint n, uint chunk,
                                 __global const uint* offsets, uint use_offsets, uint inclusive,
                                 __global uint* total_out, uint total_index, uint write_total) {
  __local uint tile[TILE];
  __local uint tmp[WG];
  const uint lid = get_local_id(0);
  const uint group = get_group_id(0);
  const uint base = group * TILE;
  /* Coalesced load into local memory, then each work-item scans ITEMS
   * consecutive elements so that work-item order is element order. */
  for (uint i = lid; i < TILE; i += WG) {
    const uint idx = base + i;
    tile[i] = idx < n ? in[idx] : 0u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  uint v[ITEMS];
  uint s = 0;
  for (uint k = 0; k < ITEMS; ++k) {
    v[k] = tile[lid * ITEMS + k];
    s += v[k];
  }
  uint total;
  const uint start = use_offsets ? offsets[group] : 0u;
  uint acc = wg_exclusive_scan(s, tmp, &total) + start;
  for (uint k = 0; k < ITEMS; ++k) {
    if (inclusive) {
      acc += v[k];
      tile[lid * ITEMS + k] = acc;
    } else {
      tile[lid * ITEMS + k] = acc;
      acc += v[k];
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint i = lid; i < TILE; i += WG) {
    const uint idx = base + i;
    if (idx < n) out[idx] = tile[i];
  }
  if (write_total && lid == 0) total_out[total_index] = start + total;
}

#else /* CPU-chunked: work-item g owns [g * chunk, (g + 1) * chunk) */

__kernel void scan_reduce(__global const uint* restrict in, __global uint* restrict partials, uint n, uint chunk) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  /* Four independent lanes so the sum is not one long dependency chain. */
  uint4 acc = (uint4)(0u);
  uint i = b;
  for (; i + 16 <= e; i += 16) {
    acc += vload4(0, in + i) + vload4(1, in + i) + vload4(2, in + i) + vload4(3, in + i);
  }
  uint s = acc.x + acc.y + acc.z + acc.w;
  for (; i < e; ++i) s += in[i];
  partials[g] = s;
}

__kernel void scan_tiles(__global const uint* in, __global uint* out, uint n, uint chunk,
                         __global const uint* offsets, uint use_offsets, uint inclusive,
                         __global uint* total_out, uint total_index, uint write_total) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  uint acc = use_offsets ? offsets[g] : 0u;
  /* Two loops rather than a per-element branch: the serial chain is the
   * bottleneck, keep nothing else in it. */
  if (inclusive) {
    for (uint i = b; i < e; ++i) {
      acc += in[i];
      out[i] = acc;
    }
  } else {
    for (uint i = b; i < e; ++i) {
      const uint x = in[i];
      out[i] = acc;
      acc += x;
    }
  }
  if (write_total) total_out[total_index] = acc;
}

#endif
