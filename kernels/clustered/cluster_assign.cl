/* Clustered shading, part 3 of 3: lights -> unique clusters, the light
 * lists (the other parts: cluster_bounds.cl builds the cluster boxes,
 * light_bvh.cl the leaves and tree, laid out as clustered/bvh_layout.cl says).
 *
 *   cluster_order         work order of the clusters (2D Morton order of tiles)
 *   assign_count/fill     per cluster, hit masks of the leaves: every leaf
 *                         (brute force) or those the BVH walk reaches
 *   (scan of the record counts between the two)
 *   write_grid            (offset, count) per cluster (common/light_grid.cl)
 *
 * Both methods run the same leaf test, so BVH lists equal brute-force lists
 * as sets (the BVH's are in Morton order, brute force's ascending).
 * cluster_order and write_grid are one work-item per cluster and serve both
 * shapes; the GPU shape writes the same records in the same order.
 *
 * Kernel shapes: the kernels without a suffix are the CPU shape (a work-item
 * per cluster with private state; PoCL runs each as a plain loop); the *_wg
 * kernels are the GPU shape of the same passes (work-groups cooperating
 * through local memory, consecutive work-items on consecutive data) with the
 * same outputs. The host picks one set (ClusterLightAssigner,
 * --kernel-shape); the GPU shape's groups are BVH_BRANCH work-items, one per
 * child of the node being tested.
 *
 * Defines: LEAF_SIZE (host: ClusterLightAssigner).
 */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#include "clustered/bvh_layout.cl"
#include "common/light_grid.cl" /* write_grid */

/* Stack of pending nodes: at most BVH_BRANCH per level plus the top level. */
#define BVH_STACK 256

/* ---------------------------------------------------------------- leaves
 *
 * Lights are tested LEAF_SIZE at a time: one loop of fixed trip count over a
 * leaf's structure of arrays turns a cluster box into a hit mask,
 * branch-free, so the compiler vectorizes it. Brute force and the BVH share
 * this routine: brute force tests every leaf of the lights in their given
 * order, the BVH only the leaves (of Morton-sorted lights) whose node boxes
 * overlap the cluster box. */

/* Eight lanes at a time in explicit vectors: PoCL runs a divergent walk one
 * work-item at a time, and LLVM does not vectorize the bit-building scalar
 * loop, so the vector types are what puts the tests in SIMD registers. Each
 * chunk of 8 ORs its lanes' bits (lane i of chunk c: bit 8c + i) into one
 * accumulator, reduced to a scalar once per leaf or block. */
inline int8 chunk_bits(int8 hit, uint c) { return hit & ((int8)(1, 2, 4, 8, 16, 32, 64, 128) << (int)(8u * c)); }

inline uint or_lanes(int8 v) {
  const int4 h4 = v.lo | v.hi;
  const int2 h2 = h4.lo | h4.hi;
  return (uint)(h2.x | h2.y);
}

inline uint leaf_mask(__global const float* soa, uint leaf, float4 lo, float4 hi) {
  __global const float* b = soa + (size_t)leaf * (4u * LEAF_SIZE);
  int8 acc = (int8)(0);
  for (uint c = 0; c < LEAF_SIZE / 8u; ++c) {
    const float8 x = vload8(c, b), y = vload8(c, b + LEAF_SIZE), d = vload8(c, b + 2u * LEAF_SIZE);
    const float8 r2 = vload8(c, b + 3u * LEAF_SIZE);
    const float8 dx = x - clamp(x, lo.x, hi.x), dy = y - clamp(y, lo.y, hi.y), dz = d - clamp(d, lo.z, hi.z);
    acc |= chunk_bits(dx * dx + dy * dy + dz * dz <= r2, c);
  }
  return or_lanes(acc);
}

/* A child is entered when its box overlaps the cluster box and its bounding
 * sphere reaches it (the sphere is much tighter than the box around a group
 * of large lights; both are padded, so every light that passes the leaf test
 * is reached). */
inline uint block_mask(__global const float* nsoa, uint block, float4 lo, float4 hi) {
  __global const float* b = nsoa + (size_t)block * (NODE_FLOATS * BVH_BRANCH);
  int8 acc = (int8)(0);
  for (uint c = 0; c < BVH_BRANCH / 8u; ++c) {
    const float8 x0 = vload8(c, b), y0 = vload8(c, b + BVH_BRANCH), z0 = vload8(c, b + 2u * BVH_BRANCH);
    const float8 x1 = vload8(c, b + 3u * BVH_BRANCH), y1 = vload8(c, b + 4u * BVH_BRANCH);
    const float8 z1 = vload8(c, b + 5u * BVH_BRANCH);
    const float8 cx = vload8(c, b + 6u * BVH_BRANCH), cy = vload8(c, b + 7u * BVH_BRANCH);
    const float8 cz = vload8(c, b + 8u * BVH_BRANCH), r = vload8(c, b + 9u * BVH_BRANCH);
    const float8 dx = cx - clamp(cx, lo.x, hi.x), dy = cy - clamp(cy, lo.y, hi.y), dz = cz - clamp(cz, lo.z, hi.z);
    /* Bitwise & of the lane masks: every test is evaluated, no branches. */
    const int8 hit = (x0 <= hi.x) & (lo.x <= x1) & (y0 <= hi.y) & (lo.y <= y1) & (z0 <= hi.z) & (lo.z <= z1) &
                     (dx * dx + dy * dy + dz * dz <= r * r) & (r >= 0.0f);
    acc |= chunk_bits(hit, c);
  }
  return or_lanes(acc);
}

/* Work order of the clusters for the assignment passes: tiles along a 2D
 * Morton curve, a tile's slices in order. Clusters that run one after the
 * other then share more of the leaves they read (the walk waits on memory,
 * not arithmetic), where key order runs along whole tile rows. The lists do
 * not depend on the order. */
inline uint spread_2d(uint v) {
  v &= 0xffffu;
  v = (v | (v << 8)) & 0x00ff00ffu;
  v = (v | (v << 4)) & 0x0f0f0f0fu;
  v = (v | (v << 2)) & 0x33333333u;
  v = (v | (v << 1)) & 0x55555555u;
  return v;
}

__kernel void cluster_order(__global const uint* keys, uint count, uint x_bits, uint k_bits, __global uint* codes,
                            __global uint* ids) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const uint key = keys[c];
  const uint k = key & ((1u << k_bits) - 1u);
  const uint i = (key >> k_bits) & ((1u << x_bits) - 1u);
  const uint j = key >> (k_bits + x_bits);
  codes[c] = ((spread_2d(i) | (spread_2d(j) << 1)) << k_bits) | k;
  ids[c] = c;
}

/* ------------------------------------------------------------ assignment
 *
 * count -> scan -> fill, one work-item per cluster with private state (the
 * CPU shape; see the PoCL notes). A cluster's light list is a list of hit
 * records (first light slot of the leaf, hit mask): the leaf test yields a
 * mask anyway, and a record stands for ~11 lights at high light densities, so
 * the lists are several times smaller than index lists and nothing has to
 * expand them on the device (the shader walks the masks, lookup_clustered.glsl).
 * The count pass walks (or, brute force, sweeps) the leaves and records each
 * hit leaf in the cluster's own slots of a scratch buffer, up to `slots` of
 * them; the fill pass copies them to the cluster's place in the list. A
 * cluster with more hit leaves than slots is walked again by the fill pass.
 * So nothing is truncated and nothing needs atomics.
 *
 * The walk keeps a stack of inner nodes whose boxes overlap the cluster box
 * (level << 27 | node); popping one tests its 32 children at once, and the
 * leaves among them test their LEAF_SIZE lights. use_bvh = 0: brute force,
 * every leaf in order. */

/* One leaf: its hit mask, then a record in the count pass's slots (mode 0,
 * while they last) or in the list (mode 1); *m counts lights, *h records. */
inline void visit_leaf(uint mode, uint leaf, __global const float* soa, float4 lo, float4 hi,
                       __global uint* rec_leaf, __global uint* rec_mask, uint slots, __global uint2* out, uint* m,
                       uint* h) {
  const uint mask = leaf_mask(soa, leaf, lo, hi);
  if (mask == 0u) return;
  if (mode == 0u) {
    if (*h < slots) {
      rec_leaf[*h] = leaf * LEAF_SIZE;
      rec_mask[*h] = mask;
    }
  } else {
    out[*h] = (uint2)(leaf * LEAF_SIZE, mask);
  }
  *m += popcount(mask);
  ++*h;
}

/* mode 0: count, recording hit leaves into rec_leaf/rec_mask (up to slots);
 * mode 1: count and write the records to out. Returns the light count and, in
 * *hit_leaves, the number of leaves with hits (records). The leaves under a node of
 * level 1 are tested straight from its children's mask, never stacked: they
 * are most of the nodes a walk reaches. */
inline uint walk(uint mode, uint use_bvh, __global const float* soa, uint n_leaves,
                 __global const float* nsoa, __global const uint* block_start, uint levels, float4 lo, float4 hi,
                 __global uint* rec_leaf, __global uint* rec_mask, uint slots, __global uint2* out, uint* hit_leaves) {
  uint m = 0u, h = 0u;
  if (!use_bvh) {
    for (uint leaf = 0; leaf < n_leaves; ++leaf)
      visit_leaf(mode, leaf, soa, lo, hi, rec_leaf, rec_mask, slots, out, &m, &h);
    *hit_leaves = h;
    return m;
  }
  const uint top = levels - 1u;
  uint mask = block_mask(nsoa, block_start[top], lo, hi);
  if (top == 0u) {
    /* One block of at most 32 leaves. */
    while (mask != 0u) {
      const uint bit = mask & (0u - mask);
      visit_leaf(mode, 31u - clz(bit), soa, lo, hi, rec_leaf, rec_mask, slots, out, &m, &h);
      mask ^= bit;
    }
    *hit_leaves = h;
    return m;
  }
  uint stack[BVH_STACK];
  uint sp = 0;
  while (mask != 0u) {
    const uint bit = mask & (0u - mask);
    stack[sp++] = (top << 27) | (31u - clz(bit));
    mask ^= bit;
  }
  while (sp != 0u) {
    const uint e = stack[--sp];
    const uint l = e >> 27, node = e & 0x7ffffffu;
    uint children = block_mask(nsoa, block_start[l - 1u] + node, lo, hi);
    if (l == 1u) {
      while (children != 0u) {
        const uint bit = children & (0u - children);
        visit_leaf(mode, node * BVH_BRANCH + (31u - clz(bit)), soa, lo, hi, rec_leaf, rec_mask, slots, out, &m, &h);
        children ^= bit;
      }
      continue;
    }
    while (children != 0u) {
      const uint bit = children & (0u - children);
      stack[sp++] = ((l - 1u) << 27) | (node * BVH_BRANCH + (31u - clz(bit)));
      children ^= bit;
    }
  }
  *hit_leaves = h;
  return m;
}

__kernel void assign_count(__global const float* soa, uint n_leaves, __global const float* nsoa,
                           __global const uint* block_start, uint levels, uint use_bvh, __global const float4* box_lo,
                           __global const float4* box_hi, uint count, __global uint* rec_leaf, __global uint* rec_mask,
                           uint slots, __global uint* hit_leaves, __global uint* counts, __global const uint* order,
                           uint use_order) {
  if (get_global_id(0) >= count) return;
  const uint c = use_order ? order[get_global_id(0)] : (uint)get_global_id(0);
  uint h = 0u;
  counts[c] = n_leaves == 0u ? 0u
                             : walk(0u, use_bvh, soa, n_leaves, nsoa, block_start, levels, box_lo[c], box_hi[c],
                                    rec_leaf + (size_t)c * slots, rec_mask + (size_t)c * slots, slots, 0, &h);
  hit_leaves[c] = h;
}

/* offsets: exclusive scan of hit_leaves (records). */
__kernel void assign_fill(__global const float* soa, uint n_leaves, __global const float* nsoa,
                          __global const uint* block_start, uint levels, uint use_bvh, __global const float4* box_lo,
                          __global const float4* box_hi, uint count, __global const uint* rec_leaf,
                          __global const uint* rec_mask, uint slots, __global const uint* hit_leaves,
                          __global const uint* offsets, __global uint2* records, __global const uint* order,
                          uint use_order) {
  if (get_global_id(0) >= count) return;
  const uint c = use_order ? order[get_global_id(0)] : (uint)get_global_id(0);
  const uint h = hit_leaves[c];
  __global uint2* out = records + offsets[c];
  if (h <= slots) {
    for (uint j = 0; j < h; ++j) out[j] = (uint2)(rec_leaf[(size_t)c * slots + j], rec_mask[(size_t)c * slots + j]);
    return;
  }
  uint unused = 0u;
  walk(1u, use_bvh, soa, n_leaves, nsoa, block_start, levels, box_lo[c], box_hi[c], 0, 0, 0u, out, &unused);
}

/* ----------------------------------------------- assignment, GPU shape
 *
 * A work-group of BVH_BRANCH (32) work-items per cluster walks the tree
 * together: a node's 32 children are tested one per work-item (the lanes of
 * block_mask), the leaves under a level-1 node (or 32 consecutive leaves,
 * brute force) one leaf per work-item (leaf_mask), and hit leaves take their
 * record slots in ascending order by a prefix count of the hit flags. The
 * stack of pending nodes lives in local memory and is pushed by work-item 0;
 * every work-item reads the same masks from local memory, so the walk's
 * control flow is uniform across the group. The walk visits nodes and
 * leaves in the CPU shape's order, so records come out in the same order. */

/* Every work-item gets the OR (or the sum) of the group's values. */
inline uint group_or(__local uint* cell, uint v) {
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0u) *cell = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (v != 0u) atomic_or(cell, v);
  barrier(CLK_LOCAL_MEM_FENCE);
  return *cell;
}
inline uint group_add(__local uint* cell, uint v) {
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0u) *cell = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (v != 0u) atomic_add(cell, v);
  barrier(CLK_LOCAL_MEM_FENCE);
  return *cell;
}

/* Lane `lane` of block_mask: does child `lane` of the block overlap the box? */
inline uint block_lane_hit(__global const float* nsoa, uint block, uint lane, float4 lo, float4 hi) {
  __global const float* b = nsoa + (size_t)block * (NODE_FLOATS * BVH_BRANCH) + lane;
  const float x0 = b[0], y0 = b[BVH_BRANCH], z0 = b[2u * BVH_BRANCH];
  const float x1 = b[3u * BVH_BRANCH], y1 = b[4u * BVH_BRANCH], z1 = b[5u * BVH_BRANCH];
  const float cx = b[6u * BVH_BRANCH], cy = b[7u * BVH_BRANCH], cz = b[8u * BVH_BRANCH], r = b[9u * BVH_BRANCH];
  const float dx = cx - clamp(cx, lo.x, hi.x), dy = cy - clamp(cy, lo.y, hi.y), dz = cz - clamp(cz, lo.z, hi.z);
  return (x0 <= hi.x && lo.x <= x1 && y0 <= hi.y && lo.y <= y1 && z0 <= hi.z && lo.z <= z1 &&
          dx * dx + dy * dy + dz * dz <= r * r && r >= 0.0f)
             ? 1u
             : 0u;
}

/* Leaves first + b for the set bits b of `bits`, one per work-item: records
 * (mode 0: into the count pass's slots while they last; mode 1: out), *m
 * lights, *h records, as visit_leaf does one leaf at a time. */
inline void visit_leaves_wg(uint mode, uint first, uint bits, __global const float* soa, float4 lo, float4 hi,
                            __global uint* rec_leaf, __global uint* rec_mask, uint slots, __global uint2* out,
                            uint* m, uint* h, __local uint* cells) {
  const uint lid = get_local_id(0);
  const uint mask = ((bits >> lid) & 1u) ? leaf_mask(soa, first + lid, lo, hi) : 0u;
  const uint flags = group_or(&cells[0], mask != 0u ? 1u << lid : 0u);
  const uint lights = group_add(&cells[1], popcount(mask));
  if (mask != 0u) {
    const uint pos = *h + popcount(flags & ((1u << lid) - 1u));
    const uint leaf = first + lid;
    if (mode == 0u) {
      if (pos < slots) {
        rec_leaf[pos] = leaf * LEAF_SIZE;
        rec_mask[pos] = mask;
      }
    } else {
      out[pos] = (uint2)(leaf * LEAF_SIZE, mask);
    }
  }
  *m += lights;
  *h += popcount(flags);
}

inline uint walk_wg(uint mode, uint use_bvh, __global const float* soa, uint n_leaves, __global const float* nsoa,
                    __global const uint* block_start, uint levels, float4 lo, float4 hi, __global uint* rec_leaf,
                    __global uint* rec_mask, uint slots, __global uint2* out, uint* hit_leaves,
                    __local uint* cells, __local uint* stack) {
  const uint lid = get_local_id(0);
  uint m = 0u, h = 0u;
  if (!use_bvh) {
    for (uint first = 0; first < n_leaves; first += BVH_BRANCH) {
      const uint k = min(BVH_BRANCH, n_leaves - first);
      visit_leaves_wg(mode, first, k == 32u ? 0xffffffffu : (1u << k) - 1u, soa, lo, hi, rec_leaf, rec_mask, slots,
                      out, &m, &h, cells);
    }
    *hit_leaves = h;
    return m;
  }
  const uint top = levels - 1u;
  uint mask = group_or(&cells[0], block_lane_hit(nsoa, block_start[top], lid, lo, hi) << lid);
  if (top == 0u) {
    visit_leaves_wg(mode, 0u, mask, soa, lo, hi, rec_leaf, rec_mask, slots, out, &m, &h, cells);
    *hit_leaves = h;
    return m;
  }
  /* Pushed in ascending bit order and popped from the top, as walk() does. */
  uint sp = 0;
  if (lid == 0u)
    for (uint b = mask, j = 0; b != 0u; b &= b - 1u, ++j) stack[j] = (top << 27) | (31u - clz(b & (0u - b)));
  sp = popcount(mask);
  while (sp != 0u) {
    barrier(CLK_LOCAL_MEM_FENCE); /* work-item 0's pushes are visible */
    const uint e = stack[--sp];
    const uint l = e >> 27, node = e & 0x7ffffffu;
    const uint children = group_or(&cells[0], block_lane_hit(nsoa, block_start[l - 1u] + node, lid, lo, hi) << lid);
    if (l == 1u) {
      visit_leaves_wg(mode, node * BVH_BRANCH, children, soa, lo, hi, rec_leaf, rec_mask, slots, out, &m, &h, cells);
      continue;
    }
    if (lid == 0u)
      for (uint b = children, j = sp; b != 0u; b &= b - 1u, ++j)
        stack[j] = ((l - 1u) << 27) | (node * BVH_BRANCH + (31u - clz(b & (0u - b))));
    sp += popcount(children);
  }
  *hit_leaves = h;
  return m;
}

__kernel void assign_count_wg(__global const float* soa, uint n_leaves, __global const float* nsoa,
                              __global const uint* block_start, uint levels, uint use_bvh,
                              __global const float4* box_lo, __global const float4* box_hi, uint count,
                              __global uint* rec_leaf, __global uint* rec_mask, uint slots, __global uint* hit_leaves,
                              __global uint* counts, __global const uint* order, uint use_order) {
  __local uint cells[2];
  __local uint stack[BVH_STACK];
  const uint g = get_group_id(0);
  if (g >= count) return; /* whole group */
  const uint c = use_order ? order[g] : g;
  uint h = 0u;
  const uint m = n_leaves == 0u ? 0u
                                : walk_wg(0u, use_bvh, soa, n_leaves, nsoa, block_start, levels, box_lo[c], box_hi[c],
                                          rec_leaf + (size_t)c * slots, rec_mask + (size_t)c * slots, slots, 0, &h,
                                          cells, stack);
  if (get_local_id(0) == 0u) {
    counts[c] = m;
    hit_leaves[c] = h;
  }
}

__kernel void assign_fill_wg(__global const float* soa, uint n_leaves, __global const float* nsoa,
                             __global const uint* block_start, uint levels, uint use_bvh,
                             __global const float4* box_lo, __global const float4* box_hi, uint count,
                             __global const uint* rec_leaf, __global const uint* rec_mask, uint slots,
                             __global const uint* hit_leaves, __global const uint* offsets, __global uint2* records,
                             __global const uint* order, uint use_order) {
  __local uint cells[2];
  __local uint stack[BVH_STACK];
  const uint g = get_group_id(0), lid = get_local_id(0);
  if (g >= count) return; /* whole group */
  const uint c = use_order ? order[g] : g;
  const uint h = hit_leaves[c];
  __global uint2* out = records + offsets[c];
  if (h <= slots) {
    for (uint j = lid; j < h; j += get_local_size(0))
      out[j] = (uint2)(rec_leaf[(size_t)c * slots + j], rec_mask[(size_t)c * slots + j]);
    return;
  }
  uint unused = 0u;
  walk_wg(1u, use_bvh, soa, n_leaves, nsoa, block_start, levels, box_lo[c], box_hi[c], 0, 0, 0u, out, &unused, cells,
          stack);
}

