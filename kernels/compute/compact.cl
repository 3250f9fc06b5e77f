/* Stable stream compaction and unique, reduce-then-scan:
 *   *_count:  kept elements per chunk (CPU) / tile (GPU),
 *   (host)    exclusive scan of the counts -> each chunk's first output slot,
 *             the total -> counts[groups], the result count,
 *   *_write:  each chunk / tile writes its kept elements from its slot on,
 *             in input order.
 * "Kept" is flags[i] != 0 (compact, compact_indices) or, on sorted keys,
 * i == 0 || keys[i] != keys[i - 1] (unique). `mode` of compact_write: 0 writes
 * in[i], 1 writes i. Both shapes take the same arguments; the work-group
 * shape ignores `chunk` (group g owns tile g of WG * ITEMS elements). */
#include "compute/prim_common.cl"

ML_INLINE uint keep_unique(__global const uint* keys, uint i) { return i == 0 || keys[i] != keys[i - 1]; }

#if !ML_GPU

__kernel void compact_count(__global const uint* restrict flags, uint n, uint chunk, __global uint* restrict counts) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  uint c = 0;
  for (uint i = b; i < e; ++i) c += flags[i] != 0;
  counts[g] = c;
}

__kernel void unique_count(__global const uint* restrict keys, uint n, uint chunk, __global uint* restrict counts) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  uint c = 0;
  for (uint i = b; i < e; ++i) c += keep_unique(keys, i);
  counts[g] = c;
}

/* offsets[g] .. offsets[g + 1] is this chunk's output range (the host stores
 * the total at offsets[groups]). The loops store every element and advance
 * only past kept ones, so random flags cost no branch mispredictions; a
 * non-kept element's store lands on the next free slot, which a later kept one
 * overwrites, or is dropped at the range end (the one predictable branch). */
__kernel void compact_write(__global const uint* restrict in, __global const uint* restrict flags,
                            __global uint* restrict out, uint n, uint chunk, uint mode,
                            __global const uint* restrict offsets) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  uint pos = offsets[g];
  const uint limit = offsets[g + 1];
  if (mode == 0) {
    for (uint i = b; i < e; ++i) {
      const uint v = in[i];
      if (pos < limit) out[pos] = v;
      pos += flags[i] != 0;
    }
  } else {
    for (uint i = b; i < e; ++i) {
      if (pos < limit) out[pos] = i;
      pos += flags[i] != 0;
    }
  }
}

__kernel void unique_write(__global const uint* restrict keys, __global uint* restrict out, uint n, uint chunk,
                           __global const uint* restrict offsets) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  uint pos = offsets[g];
  const uint limit = offsets[g + 1];
  for (uint i = b; i < e; ++i) {
    const uint k = keys[i];
    if (pos < limit) out[pos] = k;
    pos += keep_unique(keys, i);
  }
}

#else /* GPU: group g owns tile g; work-item lid owns its ITEMS consecutive elements */

ML_INLINE void count_tile(uint keep_sum, __global uint* counts, __local uint* tmp) {
  uint total;
  wg_exclusive_scan(keep_sum, tmp, &total);
  if (get_local_id(0) == 0) counts[get_group_id(0)] = total;
}

__kernel WG_ATTR void compact_count(__global const uint* flags, uint n, uint chunk, __global uint* counts) {
  __local uint tmp[WG];
  const uint base = get_group_id(0) * TILE;
  uint c = 0;
  for (uint i = get_local_id(0); i < TILE; i += WG) { /* coalesced */
    const uint idx = base + i;
    if (idx < n) c += flags[idx] != 0;
  }
  count_tile(c, counts, tmp);
}

__kernel WG_ATTR void unique_count(__global const uint* keys, uint n, uint chunk, __global uint* counts) {
  __local uint tmp[WG];
  const uint base = get_group_id(0) * TILE;
  uint c = 0;
  for (uint i = get_local_id(0); i < TILE; i += WG) {
    const uint idx = base + i;
    if (idx < n) c += keep_unique(keys, idx);
  }
  count_tile(c, counts, tmp);
}

/* Shared by compact_write and unique_write: kept[k] says whether element
 * base + lid * ITEMS + k is kept, value[k] what to write. */
ML_INLINE void write_kept(uint kept[ITEMS], uint value[ITEMS], __global uint* out, __global const uint* offsets,
                       __local uint* tmp) {
  uint s = 0;
  for (uint k = 0; k < ITEMS; ++k) s += kept[k];
  uint total;
  uint pos = wg_exclusive_scan(s, tmp, &total) + offsets[get_group_id(0)];
  for (uint k = 0; k < ITEMS; ++k)
    if (kept[k]) out[pos++] = value[k];
}

__kernel WG_ATTR void compact_write(__global const uint* in, __global const uint* flags, __global uint* out, uint n,
                                    uint chunk, uint mode, __global const uint* offsets) {
  __local uint tmp[WG];
  const uint first = get_group_id(0) * TILE + get_local_id(0) * ITEMS;
  uint kept[ITEMS], value[ITEMS];
  for (uint k = 0; k < ITEMS; ++k) {
    const uint idx = first + k;
    kept[k] = idx < n && flags[idx] != 0;
    value[k] = kept[k] ? (mode == 0 ? in[idx] : idx) : 0u;
  }
  write_kept(kept, value, out, offsets, tmp);
}

__kernel WG_ATTR void unique_write(__global const uint* keys, __global uint* out, uint n, uint chunk,
                                   __global const uint* offsets) {
  __local uint tmp[WG];
  const uint first = get_group_id(0) * TILE + get_local_id(0) * ITEMS;
  uint kept[ITEMS], value[ITEMS];
  for (uint k = 0; k < ITEMS; ++k) {
    const uint idx = first + k;
    kept[k] = idx < n && keep_unique(keys, idx);
    value[k] = kept[k] ? keys[idx] : 0u;
  }
  write_kept(kept, value, out, offsets, tmp);
}

#endif
