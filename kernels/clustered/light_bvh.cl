/* Clustered shading, part 2 of 3: the lights' leaves and BVH (the layout:
 * clustered/bvh_layout.cl; the other parts: cluster_bounds.cl,
 * cluster_assign.cl).
 *
 *   cluster_union_*       the box around every cluster box        [BVH only]
 *   light_reaches_union   flags of the lights that reach it; (compaction of
 *                         their indices), gather_spheres: their spheres
 *   light_bounds_*        bounding cube of the light centres (the Morton frame)
 *   light_morton          Morton code of each light's quantized position
 *                         (MORTON_AXIS_BITS per axis)
 *   (radix sort of the codes, light indices as payload)      [BVH only]
 *   pack_leaves           LEAF_SIZE lights per leaf as structure of arrays, and the
 *                         leaf boxes (BVH: Morton order; brute force: given order)
 *   bvh_level             nodes over 32 consecutive nodes of the level below
 *   node_blocks           the node boxes of each level as blocks of 32 siblings
 *   remap_leaf_ids        leaf slots: gathered index -> light index [BVH only]
 *
 * light_morton, light_reaches_union, gather_spheres and remap_leaf_ids are
 * one work-item per element and cluster_union_* a loop per chunk, serving
 * both shapes; the GPU shape builds the same leaves, tree and blocks in the
 * same order.
 *
 * Kernel shapes: the kernels without a suffix are the CPU shape (a work-item
 * per chunk, leaf or node with private state; PoCL runs each as a plain loop); the *_wg
 * kernels are the GPU shape of the same passes (work-groups cooperating
 * through local memory, consecutive work-items on consecutive data) with the
 * same outputs. The host picks one set (ClusterLightAssigner,
 * --kernel-shape); work-group sizes are powers of two it fits to the
 * kernel's limits, at most the *_WG bounds below.
 *
 * Defines: LEAF_SIZE, MORTON_AXIS_BITS (host: ClusterLightAssigner).
 */
#pragma OPENCL FP_CONTRACT OFF

#include "common/view_frustum.cl" /* DEPTH_EPS */
#include "clustered/bvh_layout.cl"

/* Leaves: the lights of a leaf are tested together (cluster_assign.cl's
 * leaf_mask), so pack_leaves writes them as structure of arrays. */

/* Packs lights into leaves: leaf l holds lights ids[LEAF_SIZE l ..]  (ids
 * null: the lights in their given order), and for the BVH its box (sphere
 * bounds padded by 1e-3 r: a sphere that passes the leaf test, which
 * tolerates 4 DEPTH_EPS of r^2, always overlaps it; z as positive distance
 * like the cluster boxes). */
__kernel void pack_leaves(__global const float4* spheres, __global const uint* ids, uint use_ids, uint n,
                          __global float* soa, __global uint* leaf_ids, __global float4* node_lo,
                          __global float4* node_hi, __global float4* node_sph, uint write_boxes) {
  const uint leaf = get_global_id(0);
  const uint first = leaf * LEAF_SIZE;
  if (first >= n) return;
  __global float* b = soa + (size_t)leaf * (4u * LEAF_SIZE);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  /* The leaf's view-space centres (z as distance), gathered once for the
   * bounding sphere's two passes below. */
  float4 p_leaf[LEAF_SIZE];
  /* The gathers first, all independent, so that their cache misses overlap
   * (Morton order scatters them over the light array); then the writes. */
  float4 gathered[LEAF_SIZE];
  const uint count_here = min(LEAF_SIZE, n - first);
  for (uint i = 0; i < count_here; ++i) gathered[i] = spheres[use_ids ? ids[first + i] : first + i];
  for (uint i = 0; i < LEAF_SIZE; ++i) {
    const uint k = first + i;
    if (k >= n) {
      b[i] = 0.0f;
      b[LEAF_SIZE + i] = 0.0f;
      b[2u * LEAF_SIZE + i] = 0.0f;
      b[3u * LEAF_SIZE + i] = -1.0f;
      leaf_ids[k] = 0xffffffffu;
      continue;
    }
    const uint id = use_ids ? ids[k] : k;
    const float4 s = gathered[i];
    b[i] = s.x;
    b[LEAF_SIZE + i] = s.y;
    b[2u * LEAF_SIZE + i] = -s.z;
    b[3u * LEAF_SIZE + i] = s.w * s.w * (1.0f + 4.0f * DEPTH_EPS);
    leaf_ids[k] = id;
    const float r = s.w * 1.001f + 1e-6f;
    const float4 p = (float4)(s.x, s.y, -s.z, 0.0f);
    lo = fmin(lo, p - r);
    hi = fmax(hi, p + r);
    p_leaf[i] = (float4)(p.xyz, s.w);
  }
  if (write_boxes) {
    node_lo[leaf] = lo;
    node_hi[leaf] = hi;
    /* Bounding sphere: centre of the centres' box, radius over the lights. */
    float4 clo = (float4)(INFINITY), chi = (float4)(-INFINITY);
    const uint count = min(LEAF_SIZE, n - first);
    for (uint i = 0; i < count; ++i) {
      const float4 p = (float4)(p_leaf[i].xyz, 0.0f);
      clo = fmin(clo, p);
      chi = fmax(chi, p);
    }
    const float4 c = (clo + chi) * 0.5f;
    float rad = 0.0f;
    for (uint i = 0; i < count; ++i) rad = fmax(rad, length((float4)(p_leaf[i].xyz, 0.0f) - c) + p_leaf[i].w);
    node_sph[leaf] = (float4)(c.xyz, rad * 1.001f + 1e-6f);
  }
}

/* ------------------------------------------------------------------- BVH */

inline uint spread10(uint v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/* The Morton frame: the bounding cube of the light centres, reduced in
 * chunks of MORTON_CHUNK lights (one work-item each, private state), then by
 * one work-item into frame = (lo.xyz, 1 / extent). */
#define MORTON_CHUNK 1024u
/* Work-item g's part of a box reduction: the least of lo_in and the greatest
 * of hi_in over elements [g * MORTON_CHUNK, + MORTON_CHUNK) of count (the
 * light bounds pass both as the spheres; the cluster union the box arrays). */
inline void box_part(__global const float4* lo_in, __global const float4* hi_in, uint count,
                     __global float4* part_lo, __global float4* part_hi) {
  const uint g = get_global_id(0);
  const uint first = g * MORTON_CHUNK;
  if (first >= count) return;
  const uint last = min(first + MORTON_CHUNK, count);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = first; i < last; ++i) {
    lo = fmin(lo, lo_in[i]);
    hi = fmax(hi, hi_in[i]);
  }
  part_lo[g] = lo;
  part_hi[g] = hi;
}

/* The box over the parts, for one work-item. */
inline void box_of_parts(__global const float4* part_lo, __global const float4* part_hi, uint parts, float4* lo,
                         float4* hi) {
  *lo = (float4)(INFINITY);
  *hi = (float4)(-INFINITY);
  for (uint i = 0; i < parts; ++i) {
    *lo = fmin(*lo, part_lo[i]);
    *hi = fmax(*hi, part_hi[i]);
  }
}

__kernel void light_bounds_partial(__global const float4* spheres, uint n, __global float4* part_lo,
                                   __global float4* part_hi) {
  box_part(spheres, spheres, n, part_lo, part_hi);
}

__kernel void light_bounds_final(__global const float4* part_lo, __global const float4* part_hi, uint parts,
                                 __global float4* frame) {
  if (get_global_id(0) != 0u) return;
  float4 lo, hi;
  box_of_parts(part_lo, part_hi, parts, &lo, &hi);
  const float extent = fmax(fmax(hi.x - lo.x, hi.y - lo.y), hi.z - lo.z);
  frame[0] = (float4)(lo.xyz, extent > 0.0f ? 1.0f / extent : 0.0f);
}

/* Lights that can reach a cluster: only those enter the BVH. A light whose
 * sphere misses the box around every cluster box misses each of them by the
 * leaf test's own comparisons (assign's leaf_mask: a float distance to a
 * farther bound is never smaller), so the lists do not change; at a million
 * lights about half are behind the camera or beside the view, and the sort,
 * the leaves and the tree shrink with them. One kernel of each serves both
 * shapes (plain loops over MORTON_CHUNK clusters, then over the parts). */
__kernel void cluster_union_partial(__global const float4* box_lo, __global const float4* box_hi, uint count,
                                    __global float4* part_lo, __global float4* part_hi) {
  box_part(box_lo, box_hi, count, part_lo, part_hi);
}

/* union[0] = lo, union[1] = hi over the parts. */
__kernel void cluster_union_final(__global const float4* part_lo, __global const float4* part_hi, uint parts,
                                  __global float4* box_union) {
  if (get_global_id(0) != 0u) return;
  float4 lo, hi;
  box_of_parts(part_lo, part_hi, parts, &lo, &hi);
  box_union[0] = lo;
  box_union[1] = hi;
}

/* flags[i]: light i reaches the union box (leaf_mask's test on it). */
__kernel void light_reaches_union(__global const float4* spheres, uint n, __global const float4* box_union,
                                  __global uint* flags) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 s = spheres[i], lo = box_union[0], hi = box_union[1];
  const float x = s.x, y = s.y, d = -s.z, r2 = s.w * s.w * (1.0f + 4.0f * DEPTH_EPS);
  const float dx = x - clamp(x, lo.x, hi.x), dy = y - clamp(y, lo.y, hi.y), dz = d - clamp(d, lo.z, hi.z);
  flags[i] = dx * dx + dy * dy + dz * dz <= r2 ? 1u : 0u;
}

/* out[k] = spheres[ids[k]]: the reaching lights, in light order. */
__kernel void gather_spheres(__global const float4* spheres, __global const uint* ids, uint n, __global float4* out) {
  const uint k = get_global_id(0);
  if (k < n) out[k] = spheres[ids[k]];
}

/* Leaf slots held indices into the gathered lights; they become light indices. */
__kernel void remap_leaf_ids(__global uint* leaf_ids, uint slots, __global const uint* ids) {
  const uint k = get_global_id(0);
  if (k >= slots) return;
  const uint v = leaf_ids[k];
  if (v != 0xffffffffu) leaf_ids[k] = ids[v];
}

/* Quantized in the cube [lo, lo + extent] of frame[0]; positions outside
 * (none, with the frame above) would clamp, which only costs tree quality.
 * 8 bits per axis (the host's default) make 3 radix passes of 8 bits instead
 * of 4: lights that share a cell of 1/256 of the extent keep their input
 * order, which at 32 lights per leaf costs nothing measurable. */
#ifndef MORTON_AXIS_BITS
#define MORTON_AXIS_BITS 10u
#endif
__kernel void light_morton(__global const float4* spheres, uint n, __global const float4* frame,
                           __global uint* codes, __global uint* ids) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 s = spheres[i];
  const float4 f = frame[0];
  const float3 t = clamp((s.xyz - f.xyz) * f.w, 0.0f, 1.0f) * (float)((1u << MORTON_AXIS_BITS) - 1u);
  codes[i] = spread10((uint)t.x) | (spread10((uint)t.y) << 1) | (spread10((uint)t.z) << 2);
  ids[i] = i;
}

/* Children at [child_start, child_start + n_children), parents from parent_start. */
__kernel void bvh_level(__global float4* node_lo, __global float4* node_hi, __global float4* node_sph,
                        uint child_start, uint n_children, uint parent_start) {
  const uint node = get_global_id(0);
  const uint first = node * BVH_BRANCH;
  if (first >= n_children) return;
  const uint last = min(first + BVH_BRANCH, n_children);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY), clo = (float4)(INFINITY), chi = (float4)(-INFINITY);
  for (uint i = first; i < last; ++i) {
    lo = fmin(lo, node_lo[child_start + i]);
    hi = fmax(hi, node_hi[child_start + i]);
    const float4 s = node_sph[child_start + i];
    clo = fmin(clo, (float4)(s.xyz, 0.0f));
    chi = fmax(chi, (float4)(s.xyz, 0.0f));
  }
  const float4 c = (clo + chi) * 0.5f;
  float rad = 0.0f;
  for (uint i = first; i < last; ++i) {
    const float4 s = node_sph[child_start + i];
    rad = fmax(rad, length((float4)(s.xyz, 0.0f) - c) + s.w);
  }
  node_lo[parent_start + node] = lo;
  node_hi[parent_start + node] = hi;
  node_sph[parent_start + node] = (float4)(c.xyz, rad * 1.001f + 1e-6f);
}

/* Node boxes again as structure of arrays, in blocks of 32 siblings: node i
 * of level l is lane i % 32 of block block_start[l] + i / 32 (lo.x, lo.y,
 * lo.z, hi.x, hi.y, hi.z, 32 floats each). The children of node i of level
 * l + 1 are exactly block i of level l, so one branch-free loop tests them
 * all against a cluster box, like the lights of a leaf. Lanes past the
 * level's end are empty boxes (lo +inf, hi -inf) and never overlap. */
__kernel void node_blocks(__global const float4* node_lo, __global const float4* node_hi,
                          __global const float4* node_sph, uint start, uint count, uint block_start,
                          __global float* nsoa) {
  const uint b = get_global_id(0);
  if (b * BVH_BRANCH >= count) return;
  __global float* o = nsoa + (size_t)(block_start + b) * (NODE_FLOATS * BVH_BRANCH);
  for (uint i = 0; i < BVH_BRANCH; ++i) {
    const uint k = b * BVH_BRANCH + i;
    const float4 lo = k < count ? node_lo[start + k] : (float4)(INFINITY);
    const float4 hi = k < count ? node_hi[start + k] : (float4)(-INFINITY);
    const float4 s = k < count ? node_sph[start + k] : (float4)(0.0f, 0.0f, 0.0f, -1.0f);
    o[i] = lo.x;
    o[BVH_BRANCH + i] = lo.y;
    o[2u * BVH_BRANCH + i] = lo.z;
    o[3u * BVH_BRANCH + i] = hi.x;
    o[4u * BVH_BRANCH + i] = hi.y;
    o[5u * BVH_BRANCH + i] = hi.z;
    o[6u * BVH_BRANCH + i] = s.x;
    o[7u * BVH_BRANCH + i] = s.y;
    o[8u * BVH_BRANCH + i] = s.z;
    o[9u * BVH_BRANCH + i] = s.w;
  }
}

/* ============================================================ GPU shape */

#define RED_WG 256 /* light_bounds_*_wg: most work-items per group */

/* Tree reductions over the work-group (power-of-two size) through `buf`
 * (one float4 per work-item); every work-item gets the result. min/max are
 * exact, so the order of the tree does not change the value. */
inline float4 group_min4(__local float4* buf, float4 v) {
  const uint lid = get_local_id(0);
  buf[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint s = get_local_size(0) / 2u; s > 0u; s >>= 1) {
    if (lid < s) buf[lid] = fmin(buf[lid], buf[lid + s]);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const float4 r = buf[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return r;
}
inline float4 group_max4(__local float4* buf, float4 v) {
  const uint lid = get_local_id(0);
  buf[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint s = get_local_size(0) / 2u; s > 0u; s >>= 1) {
    if (lid < s) buf[lid] = fmax(buf[lid], buf[lid + s]);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const float4 r = buf[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return r;
}

/* The Morton frame, GPU shape: a work-group per MORTON_CHUNK lights (the
 * CPU shape's parts, so the same partial boxes), read by consecutive
 * work-items and reduced in local memory; then one work-group over the parts. */
__kernel void light_bounds_partial_wg(__global const float4* spheres, uint n, __global float4* part_lo,
                                      __global float4* part_hi) {
  __local float4 buf[RED_WG];
  const uint g = get_group_id(0), lid = get_local_id(0);
  const uint first = g * MORTON_CHUNK, last = min(first + MORTON_CHUNK, n);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = first + lid; i < last; i += get_local_size(0)) {
    const float4 s = spheres[i];
    lo = fmin(lo, s);
    hi = fmax(hi, s);
  }
  lo = group_min4(buf, lo);
  hi = group_max4(buf, hi);
  if (lid == 0u) {
    part_lo[g] = lo;
    part_hi[g] = hi;
  }
}

__kernel void light_bounds_final_wg(__global const float4* part_lo, __global const float4* part_hi, uint parts,
                                    __global float4* frame) {
  __local float4 buf[RED_WG];
  const uint lid = get_local_id(0);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = lid; i < parts; i += get_local_size(0)) {
    lo = fmin(lo, part_lo[i]);
    hi = fmax(hi, part_hi[i]);
  }
  lo = group_min4(buf, lo);
  hi = group_max4(buf, hi);
  if (lid == 0u) {
    const float extent = fmax(fmax(hi.x - lo.x, hi.y - lo.y), hi.z - lo.z);
    frame[0] = (float4)(lo.xyz, extent > 0.0f ? 1.0f / extent : 0.0f);
  }
}

/* Leaves, GPU shape: a work-group of LEAF_SIZE work-items per leaf, one per
 * light; the leaf box and bounding sphere are group reductions of the values
 * pack_leaves folds one light at a time. */
__kernel void pack_leaves_wg(__global const float4* spheres, __global const uint* ids, uint use_ids, uint n,
                             __global float* soa, __global uint* leaf_ids, __global float4* node_lo,
                             __global float4* node_hi, __global float4* node_sph, uint write_boxes) {
  __local float4 buf[LEAF_SIZE];
  const uint leaf = get_group_id(0), i = get_local_id(0);
  const uint first = leaf * LEAF_SIZE, k = first + i;
  if (first >= n) return; /* whole group */
  __global float* b = soa + (size_t)leaf * (4u * LEAF_SIZE);
  const bool valid = k < n;
  float4 p = (float4)(0.0f), lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  float w = 0.0f;
  if (!valid) {
    b[i] = 0.0f;
    b[LEAF_SIZE + i] = 0.0f;
    b[2u * LEAF_SIZE + i] = 0.0f;
    b[3u * LEAF_SIZE + i] = -1.0f;
    leaf_ids[k] = 0xffffffffu;
  } else {
    const uint id = use_ids ? ids[k] : k;
    const float4 s = spheres[id];
    b[i] = s.x;
    b[LEAF_SIZE + i] = s.y;
    b[2u * LEAF_SIZE + i] = -s.z;
    b[3u * LEAF_SIZE + i] = s.w * s.w * (1.0f + 4.0f * DEPTH_EPS);
    leaf_ids[k] = id;
    const float r = s.w * 1.001f + 1e-6f;
    p = (float4)(s.x, s.y, -s.z, 0.0f);
    lo = p - r;
    hi = p + r;
    w = s.w;
  }
  if (!write_boxes) return; /* uniform */
  lo = group_min4(buf, lo);
  hi = group_max4(buf, hi);
  const float4 clo = group_min4(buf, valid ? p : (float4)(INFINITY));
  const float4 chi = group_max4(buf, valid ? p : (float4)(-INFINITY));
  const float4 c = (clo + chi) * 0.5f;
  const float rad = group_max4(buf, (float4)(valid ? length(p - c) + w : 0.0f)).x;
  if (i == 0u) {
    node_lo[leaf] = lo;
    node_hi[leaf] = hi;
    node_sph[leaf] = (float4)(c.xyz, rad * 1.001f + 1e-6f);
  }
}

/* A BVH level, GPU shape: a work-group of BVH_BRANCH work-items per parent,
 * one per child. */
__kernel void bvh_level_wg(__global float4* node_lo, __global float4* node_hi, __global float4* node_sph,
                           uint child_start, uint n_children, uint parent_start) {
  __local float4 buf[BVH_BRANCH];
  const uint node = get_group_id(0), i = get_local_id(0);
  const uint first = node * BVH_BRANCH, k = first + i;
  if (first >= n_children) return; /* whole group */
  const bool valid = k < n_children;
  const float4 s = valid ? node_sph[child_start + k] : (float4)(0.0f);
  const float4 p = (float4)(s.xyz, 0.0f);
  const float4 lo = group_min4(buf, valid ? node_lo[child_start + k] : (float4)(INFINITY));
  const float4 hi = group_max4(buf, valid ? node_hi[child_start + k] : (float4)(-INFINITY));
  const float4 clo = group_min4(buf, valid ? p : (float4)(INFINITY));
  const float4 chi = group_max4(buf, valid ? p : (float4)(-INFINITY));
  const float4 c = (clo + chi) * 0.5f;
  const float rad = group_max4(buf, (float4)(valid ? length(p - c) + s.w : 0.0f)).x;
  if (i == 0u) {
    node_lo[parent_start + node] = lo;
    node_hi[parent_start + node] = hi;
    node_sph[parent_start + node] = (float4)(c.xyz, rad * 1.001f + 1e-6f);
  }
}

/* Node blocks, GPU shape: a work-item per lane, so that each of the ten
 * arrays of a block is written by consecutive work-items. */
__kernel void node_blocks_wg(__global const float4* node_lo, __global const float4* node_hi,
                             __global const float4* node_sph, uint start, uint count, uint block_start,
                             __global float* nsoa) {
  const uint gid = get_global_id(0), b = gid / BVH_BRANCH, i = gid % BVH_BRANCH;
  if (b * BVH_BRANCH >= count) return;
  __global float* o = nsoa + (size_t)(block_start + b) * (NODE_FLOATS * BVH_BRANCH);
  const uint k = gid;
  const float4 lo = k < count ? node_lo[start + k] : (float4)(INFINITY);
  const float4 hi = k < count ? node_hi[start + k] : (float4)(-INFINITY);
  const float4 s = k < count ? node_sph[start + k] : (float4)(0.0f, 0.0f, 0.0f, -1.0f);
  o[i] = lo.x;
  o[BVH_BRANCH + i] = lo.y;
  o[2u * BVH_BRANCH + i] = lo.z;
  o[3u * BVH_BRANCH + i] = hi.x;
  o[4u * BVH_BRANCH + i] = hi.y;
  o[5u * BVH_BRANCH + i] = hi.z;
  o[6u * BVH_BRANCH + i] = s.x;
  o[7u * BVH_BRANCH + i] = s.y;
  o[8u * BVH_BRANCH + i] = s.z;
  o[9u * BVH_BRANCH + i] = s.w;
}
