/* Clustered shading: cluster keys per pixel and the unique-cluster list.
 *
 *   cluster_keys          depth -> key = ((j << XB | i) << KB) | k per pixel,
 *                         CLUSTER_INVALID for sky (is_sky_depth, gpu_types.h)
 *   page table (Karas):   page_mark -> (scan) -> page_store -> (compact of the
 *                         slot flags) -> page_unique -> page_map
 *   sort + unique:        sort_init -> (radix sort) -> head_flags -> (scan) -> run_scatter
 *   per-tile sort:        tile_gather -> (segmented sort) -> head_flags -> (scan) -> run_scatter
 *
 * The tile sits above the slice in the key, so ascending keys are tile-major:
 * all three methods produce the same ascending unique list and the same
 * pixel -> cluster map, which is what lets the tests hold them to each other.
 * The slice is found by binary search in host-computed boundaries instead of
 * log(): OpenCL's log() is not correctly rounded, comparisons are, so the C++
 * reference (host/clustered/ClusterGeometry.cpp) agrees bit for bit.
 */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#define CLUSTER_INVALID 0xffffffffu

/* Largest k in [0, slices) with bounds[k] <= z (0 when z < near). */
inline uint slice_of(float z, __global const float* bounds, uint slices) {
  uint lo = 0, hi = slices;
  while (hi - lo > 1u) {
    const uint mid = (lo + hi) / 2u;
    if (bounds[mid] <= z) lo = mid;
    else hi = mid;
  }
  return lo;
}

__kernel void cluster_keys(__global const float* depth, CameraParams cam, __global const float* slice_bounds,
                           uint slices, uint tile, uint x_bits, uint k_bits, __global uint* keys) {
  const uint p = get_global_id(0);
  if (p >= cam.width * cam.height) return;
  const float d = depth[p];
  if (is_sky_depth(d)) { /* NaN counts as sky too */
    keys[p] = CLUSTER_INVALID;
    return;
  }
  const uint y = p / cam.width, x = p - y * cam.width; /* no `%`: see tile_minmax in reduce.cl */
  const uint k = slice_of(linear_depth(d, &cam), slice_bounds, slices);
  keys[p] = ((((y / tile) << x_bits) | (x / tile)) << k_bits) | k;
}

/* ------------------------------------------------------------ page table */

/* Racing writes all store 1, so no atomics are needed. */
__kernel void page_mark(__global const uint* keys, uint n, uint page_bits, __global uint* marks) {
  const uint p = get_global_id(0);
  if (p >= n) return;
  const uint key = keys[p];
  if (key != CLUSTER_INVALID) marks[key >> page_bits] = 1u;
}

/* page_table[v] = physical page of virtual page v (exclusive scan of marks). */
__kernel void page_store(__global const uint* keys, uint n, uint page_bits, __global const uint* page_table,
                         __global uint* slots) {
  const uint p = get_global_id(0);
  if (p >= n) return;
  const uint key = keys[p];
  if (key == CLUSTER_INVALID) return;
  slots[(page_table[key >> page_bits] << page_bits) | (key & ((1u << page_bits) - 1u))] = 1u;
}

/* Inverse page table: physical -> virtual. */
__kernel void page_inverse(__global const uint* marks, __global const uint* page_table, uint n_pages,
                           __global uint* phys_to_virt) {
  const uint v = get_global_id(0);
  if (v >= n_pages) return;
  if (marks[v]) phys_to_virt[page_table[v]] = v;
}

/* used_slots: the compacted slot indices, ascending. Writes the cluster's key
 * and, into the slot itself, its cluster index (the slot flags are done). */
__kernel void page_unique(__global const uint* used_slots, uint count, uint page_bits,
                          __global const uint* phys_to_virt, __global uint* unique_keys, __global uint* slots) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const uint s = used_slots[c];
  unique_keys[c] = (phys_to_virt[s >> page_bits] << page_bits) | (s & ((1u << page_bits) - 1u));
  slots[s] = c;
}

__kernel void page_map(__global const uint* keys, uint n, uint page_bits, __global const uint* page_table,
                       __global const uint* slots, __global uint* cluster_of) {
  const uint p = get_global_id(0);
  if (p >= n) return;
  const uint key = keys[p];
  cluster_of[p] = key == CLUSTER_INVALID
                      ? CLUSTER_INVALID
                      : slots[(page_table[key >> page_bits] << page_bits) | (key & ((1u << page_bits) - 1u))];
}

/* ------------------------------------------------------ sort-based unique */

__kernel void sort_init(__global const uint* keys, uint n, __global uint* sort_keys, __global uint* sort_vals) {
  const uint p = get_global_id(0);
  if (p >= n) return;
  sort_keys[p] = keys[p];
  sort_vals[p] = p;
}

/* Pixels in tile-major order: tile t owns [offsets[t], offsets[t + 1]), rows
 * inside the tile, so each tile is one segment for the segmented sort. */
__kernel void tile_gather(__global const uint* keys, uint width, uint height, uint tile, uint tiles_x,
                          __global const uint* offsets, __global uint* sort_keys, __global uint* sort_vals) {
  const uint p = get_global_id(0);
  if (p >= width * height) return;
  const uint y = p / width, x = p - y * width;
  const uint tx = x / tile, ty = y / tile;
  const uint w = min(tile, width - tx * tile);
  const uint pos = offsets[ty * tiles_x + tx] + (y - ty * tile) * w + (x - tx * tile);
  sort_keys[pos] = keys[p];
  sort_vals[pos] = p;
}

/* Valid keys that start a run. After the per-tile sort the invalid keys sit
 * at the end of each tile's segment; the valid key after them belongs to
 * another tile, so it differs from its predecessor and is a head, as it
 * should be. */
__kernel void head_flags(__global const uint* sorted, uint n, __global uint* flags) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint key = sorted[i];
  flags[i] = (key != CLUSTER_INVALID && (i == 0u || key != sorted[i - 1u])) ? 1u : 0u;
}

/* rank: exclusive scan of flags. */
__kernel void run_scatter(__global const uint* sorted, __global const uint* sorted_vals, uint n,
                          __global const uint* flags, __global const uint* rank, __global uint* unique_keys,
                          __global uint* cluster_of) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const uint key = sorted[i];
  if (key == CLUSTER_INVALID) {
    cluster_of[sorted_vals[i]] = CLUSTER_INVALID;
    return;
  }
  const uint c = rank[i] + flags[i] - 1u;
  if (flags[i]) unique_keys[c] = key;
  cluster_of[sorted_vals[i]] = c;
}
