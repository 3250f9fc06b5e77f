/* Clustered shading: lights -> unique clusters.
 *
 *   light_view            world lights -> view-space spheres
 *   cluster_boxes         unique keys -> view-space AABB of each sub-frustum
 *                         (implicit bounds), or
 *   cluster_pixel_boxes   depth + pixel -> cluster map -> view-space AABB of
 *                         each cluster's pixels (explicit bounds)
 *   light_bounds_*        bounding cube of the light centres (the Morton frame)
 *   light_morton          Morton code of each light's quantized position
 *                         (MORTON_AXIS_BITS per axis)
 *   (radix sort of the codes, light indices as payload)      [BVH only]
 *   pack_leaves           LEAF_SIZE lights per leaf as structure of arrays, and the
 *                         leaf boxes (BVH: Morton order; brute force: given order)
 *   bvh_level             nodes over 32 consecutive nodes of the level below
 *   node_blocks           the node boxes of each level as blocks of 32 siblings
 *   assign_count/fill     per cluster, hit masks of the leaves: every leaf
 *                         (brute force) or those the BVH walk reaches
 *
 * Both methods run the same leaf test, so BVH lists equal brute-force lists
 * as sets (the BVH's are in Morton order, brute force's ascending).
 *
 * Kernel shapes: the kernels above are the CPU shape (a work-item per tile,
 * chunk, leaf, node or cluster with private state; PoCL runs each as a plain
 * loop). The *_wg kernels at the end are the GPU shape of the same passes
 * (work-groups cooperating through local memory, consecutive work-items on
 * consecutive data) with the same outputs: the same boxes, leaves, tree and
 * records in the same order. light_view, cluster_boxes, light_morton and
 * cluster_order are one work-item per light or cluster with coalesced
 * reads and writes and serve both shapes.
 * Mirrors host/clustered/ClusterGeometry.cpp (no contraction on either side).
 */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#define BVH_BRANCH 32u
/* Lights per leaf (host: ClusterLightAssigner's leaf size). Leaves are tested
 * whole in one branch-free loop; small leaves (8: one AVX vector) test fewer
 * lights that miss, wide ones suit a GPU's SIMD width. */
#ifndef LEAF_SIZE
#define LEAF_SIZE 32u
#endif
/* Stack of pending nodes: at most BVH_BRANCH per level plus the top level. */
#define BVH_STACK 256
#define DEPTH_EPS 1e-4f
/* Per BVH node in a sibling block: box lo.xyz, hi.xyz, bounding sphere xyzr. */
#define NODE_FLOATS 10u

inline float4 mat_mul(const float* m, float4 v) {
  return (float4)(m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12] * v.w,
                  m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13] * v.w,
                  m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14] * v.w,
                  m[3] * v.x + m[7] * v.y + m[11] * v.z + m[15] * v.w);
}

__kernel void light_view(__global const PointLight* lights, uint n, CameraParams cam, __global float4* spheres) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const PointLight l = lights[i];
  float4 c = mat_mul(cam.view, (float4)(l.position_radius.xyz, 1.0f));
  c.w = l.position_radius.w;
  spheres[i] = c;
}

inline float view_coord(float n, float d, float p_diag, float p_off) { return d * (n + p_off) / p_diag; }

/* lo = (x0, y0, z0), hi = (x1, y1, z1); z as positive distance. */
__kernel void cluster_boxes(__global const uint* keys, uint count, CameraParams cam, __global const float* bounds,
                            uint tile, uint x_bits, uint k_bits, __global float4* box_lo, __global float4* box_hi) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const uint key = keys[c];
  const uint k = key & ((1u << k_bits) - 1u);
  const uint i = (key >> k_bits) & ((1u << x_bits) - 1u);
  const uint j = key >> (k_bits + x_bits);
  const float xl = 2.0f * (float)(i * tile) / (float)cam.width - 1.0f;
  const float xr = 2.0f * (float)min((i + 1u) * tile, cam.width) / (float)cam.width - 1.0f;
  const float yb = 2.0f * (float)(j * tile) / (float)cam.height - 1.0f;
  const float yt = 2.0f * (float)min((j + 1u) * tile, cam.height) / (float)cam.height - 1.0f;
  const float zmin = k == 0u ? 0.0f : bounds[k] - bounds[k] * DEPTH_EPS;
  const float zmax = bounds[k + 1u] + bounds[k + 1u] * DEPTH_EPS;
  const float p00 = cam.proj[0], p20 = cam.proj[8], p11 = cam.proj[5], p21 = cam.proj[9];
  const float x0 = fmin(fmin(view_coord(xl, zmin, p00, p20), view_coord(xl, zmax, p00, p20)),
                        fmin(view_coord(xr, zmin, p00, p20), view_coord(xr, zmax, p00, p20)));
  const float x1 = fmax(fmax(view_coord(xl, zmin, p00, p20), view_coord(xl, zmax, p00, p20)),
                        fmax(view_coord(xr, zmin, p00, p20), view_coord(xr, zmax, p00, p20)));
  const float y0 = fmin(fmin(view_coord(yb, zmin, p11, p21), view_coord(yb, zmax, p11, p21)),
                        fmin(view_coord(yt, zmin, p11, p21), view_coord(yt, zmax, p11, p21)));
  const float y1 = fmax(fmax(view_coord(yb, zmin, p11, p21), view_coord(yb, zmax, p11, p21)),
                        fmax(view_coord(yt, zmin, p11, p21), view_coord(yt, zmax, p11, p21)));
  box_lo[c] = (float4)(x0, y0, zmin, 0.0f);
  box_hi[c] = (float4)(x1, y1, zmax, 0.0f);
}

/* The widening of an explicit box (see cluster_pixel_boxes), shared by both shapes. */
inline void widen_pixel_box(float4 lo, float4 hi, float4* out_lo, float4* out_hi) {
  const float ext = fmax(fmax(hi.z, fmax(fabs(lo.x), fabs(hi.x))), fmax(fabs(lo.y), fabs(hi.y)));
  const float pad = ext * DEPTH_EPS;
  *out_lo = (float4)(lo.x - pad, lo.y - pad, lo.z - lo.z * DEPTH_EPS, 0.0f);
  *out_hi = (float4)(hi.x + pad, hi.y + pad, hi.z + hi.z * DEPTH_EPS, 0.0f);
}

/* Explicit bounds (Olsson et al.): per unique cluster the view-space AABB of
 * the pixel centres that fall in it, reconstructed from the depth buffer.
 * One work-item per screen tile: unique clusters are ascending keys with the
 * tile above the slice, so the clusters of one tile form one index range that
 * no other tile touches; the work-item owns it and needs no atomics. Runs of
 * equal clusters along a row are reduced in registers. box_lo/box_hi start
 * as +inf/-inf (filled by the host). The box is then widened by DEPTH_EPS,
 * relative to its extent, so that the shader's own position (another float
 * path, or the forward pass's interpolated position) stays inside: reversed-Z
 * float depth pins the distance down to ~1e-7 (relative) at any distance and
 * any near plane (host/shared/depth_convention.h), and DEPTH_EPS leaves room
 * for the rasteriser's interpolation of both.
 * One division per pixel (the depth); the rest are products with
 * reciprocals computed once, mirrored by host/clustered/ClusterGeometry.cpp. */
__kernel void cluster_pixel_boxes(__global const float* depth, __global const uint* cluster_of, CameraParams cam,
                                  uint tile, uint tiles_x, uint n_tiles, __global float4* box_lo,
                                  __global float4* box_hi) {
  const uint t = get_global_id(0);
  if (t >= n_tiles) return;
  const uint ty = t / tiles_x, x0 = (t - ty * tiles_x) * tile, y0 = ty * tile; /* no `%`: see reduce.cl */
  const uint x1 = min(x0 + tile, cam.width), y1 = min(y0 + tile, cam.height);
  const float sx = 2.0f / (float)cam.width, sy = 2.0f / (float)cam.height;
  const float ix = 1.0f / cam.proj[0], iy = 1.0f / cam.proj[5], ox = cam.proj[8], oy = cam.proj[9];
  uint cmin = 0xffffffffu, cmax = 0u;
  for (uint y = y0; y < y1; ++y) {
    const float fy = (((float)y + 0.5f) * sy - 1.0f + oy) * iy;
    uint cur = 0xffffffffu;
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (uint x = x0; x < x1; ++x) {
      const uint p = y * cam.width + x;
      const uint c = cluster_of[p];
      if (c == 0xffffffffu) continue;
      if (c != cur) {
        if (cur != 0xffffffffu) {
          box_lo[cur] = fmin(box_lo[cur], lo);
          box_hi[cur] = fmax(box_hi[cur], hi);
        }
        cur = c;
        cmin = min(cmin, c);
        cmax = max(cmax, c);
        lo = (float4)(INFINITY);
        hi = (float4)(-INFINITY);
      }
      const float z = linear_depth(depth[p], &cam);
      const float fx = (((float)x + 0.5f) * sx - 1.0f + ox) * ix;
      const float4 v = (float4)(z * fx, z * fy, z, 0.0f);
      lo = fmin(lo, v);
      hi = fmax(hi, v);
    }
    if (cur != 0xffffffffu) {
      box_lo[cur] = fmin(box_lo[cur], lo);
      box_hi[cur] = fmax(box_hi[cur], hi);
    }
  }
  for (uint c = cmin; c <= cmax && cmin <= cmax; ++c) {
    float4 lo, hi;
    widen_pixel_box(box_lo[c], box_hi[c], &lo, &hi);
    box_lo[c] = lo;
    box_hi[c] = hi;
  }
}

/* ---------------------------------------------------------------- leaves
 *
 * Lights are tested LEAF_SIZE at a time: a leaf holds LEAF_SIZE lights as
 * structure of arrays (x, y, distance -z, r^2 (1 + 4 DEPTH_EPS)) and one loop
 * of fixed trip count turns a cluster box into a hit mask, branch-free, so the
 * compiler vectorizes it. Brute force and the BVH share this routine: brute
 * force tests every leaf of the lights in their given order, the BVH only the
 * leaves (of Morton-sorted lights) whose node boxes overlap the cluster box.
 * Padding lights have r^2 = -1 and never hit. */

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
    const float4 s = spheres[id];
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
__kernel void light_bounds_partial(__global const float4* spheres, uint n, __global float4* part_lo,
                                   __global float4* part_hi) {
  const uint g = get_global_id(0);
  const uint first = g * MORTON_CHUNK;
  if (first >= n) return;
  const uint last = min(first + MORTON_CHUNK, n);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = first; i < last; ++i) {
    const float4 s = spheres[i];
    lo = fmin(lo, s);
    hi = fmax(hi, s);
  }
  part_lo[g] = lo;
  part_hi[g] = hi;
}

__kernel void light_bounds_final(__global const float4* part_lo, __global const float4* part_hi, uint parts,
                                 __global float4* frame) {
  if (get_global_id(0) != 0u) return;
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = 0; i < parts; ++i) {
    lo = fmin(lo, part_lo[i]);
    hi = fmax(hi, part_hi[i]);
  }
  const float extent = fmax(fmax(hi.x - lo.x, hi.y - lo.y), hi.z - lo.z);
  frame[0] = (float4)(lo.xyz, extent > 0.0f ? 1.0f / extent : 0.0f);
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

/* ============================================================ GPU shape
 *
 * Same outputs as the CPU-shaped kernels above; the host picks one set
 * (ClusterLightAssigner, --kernel-shape). Work-group sizes are powers of two
 * fitted by the host to the kernel's limits, at most the *_WG bounds below. */

#define PIX_WG 256   /* cluster_pixel_boxes_wg: most work-items per tile */
#define PIX_SLOTS 64 /* clusters of a tile reduced in local memory; the rest use global atomics */
#define RED_WG 256   /* light_bounds_*_wg: most work-items per group */

/* A float as an int that orders like the float, for atomic_min/max. */
inline int ordered_int(float f) {
  const int i = as_int(f);
  return i >= 0 ? i : i ^ 0x7fffffff;
}
inline float from_ordered_int(int i) { return as_float(i >= 0 ? i : i ^ 0x7fffffff); }
#define ORDERED_INF 0x7f800000          /* ordered_int(+INFINITY) */
#define ORDERED_NEG_INF ((int)0x807fffff) /* ordered_int(-INFINITY) */

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

/* Explicit bounds, GPU shape: a work-group per screen tile, its work-items
 * over the tile's pixels (consecutive pixels of a row on consecutive items).
 * The tile's clusters are one index range from its smallest cluster (see
 * cluster_pixel_boxes), so the first PIX_SLOTS of them are reduced with local
 * atomics and written by the group, which owns them; clusters past that use
 * global atomics. Boxes are ordered ints here (host fills ORDERED_INF /
 * ORDERED_NEG_INF); cluster_boxes_finish turns them into widened floats. */
__kernel void cluster_pixel_boxes_wg(__global const float* depth, __global const uint* cluster_of, CameraParams cam,
                                     uint tile, uint tiles_x, __global int4* box_lo, __global int4* box_hi) {
  __local uint lbase;
  __local int llo[PIX_SLOTS * 3], lhi[PIX_SLOTS * 3];
  const uint t = get_group_id(0), lid = get_local_id(0), lsize = get_local_size(0);
  const uint ty = t / tiles_x, x0 = (t - ty * tiles_x) * tile, y0 = ty * tile; /* no `%`: see reduce.cl */
  const uint w = min(x0 + tile, cam.width) - x0, npx = w * (min(y0 + tile, cam.height) - y0);
  const float sx = 2.0f / (float)cam.width, sy = 2.0f / (float)cam.height;
  const float ix = 1.0f / cam.proj[0], iy = 1.0f / cam.proj[5], ox = cam.proj[8], oy = cam.proj[9];
  if (lid == 0u) lbase = 0xffffffffu;
  for (uint i = lid; i < PIX_SLOTS * 3u; i += lsize) {
    llo[i] = ORDERED_INF;
    lhi[i] = ORDERED_NEG_INF;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint i = lid; i < npx; i += lsize) {
    const uint row = i / w;
    const uint c = cluster_of[(y0 + row) * cam.width + x0 + (i - row * w)];
    if (c != 0xffffffffu) atomic_min(&lbase, c);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint base = lbase;
  __global int* glo = (__global int*)box_lo;
  __global int* ghi = (__global int*)box_hi;
  for (uint i = lid; i < npx; i += lsize) {
    const uint row = i / w, x = x0 + (i - row * w), y = y0 + row, p = y * cam.width + x;
    const uint c = cluster_of[p];
    if (c == 0xffffffffu) continue;
    const float z = linear_depth(depth[p], &cam);
    const float fx = (((float)x + 0.5f) * sx - 1.0f + ox) * ix;
    const float fy = (((float)y + 0.5f) * sy - 1.0f + oy) * iy;
    const int v[3] = {ordered_int(z * fx), ordered_int(z * fy), ordered_int(z)};
    const bool local_slot = c - base < PIX_SLOTS;
    for (uint a = 0; a < 3u; ++a) {
      if (local_slot) {
        atomic_min(&llo[(c - base) * 3u + a], v[a]);
        atomic_max(&lhi[(c - base) * 3u + a], v[a]);
      } else {
        atomic_min(&glo[(size_t)c * 4u + a], v[a]);
        atomic_max(&ghi[(size_t)c * 4u + a], v[a]);
      }
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  /* A used slot's cluster belongs to this tile alone (unused: z still +inf). */
  for (uint s = lid; s < PIX_SLOTS; s += lsize)
    if (base != 0xffffffffu && llo[s * 3u + 2u] != ORDERED_INF) {
      box_lo[base + s] = (int4)(llo[s * 3u], llo[s * 3u + 1u], llo[s * 3u + 2u], 0);
      box_hi[base + s] = (int4)(lhi[s * 3u], lhi[s * 3u + 1u], lhi[s * 3u + 2u], 0);
    }
}

/* Ordered ints -> floats, widened as the CPU shape does. */
__kernel void cluster_boxes_finish(__global float4* box_lo, __global float4* box_hi, uint count, CameraParams cam) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const int4 l = as_int4(box_lo[c]), h = as_int4(box_hi[c]);
  const float4 lo = (float4)(from_ordered_int(l.x), from_ordered_int(l.y), from_ordered_int(l.z), 0.0f);
  const float4 hi = (float4)(from_ordered_int(h.x), from_ordered_int(h.y), from_ordered_int(h.z), 0.0f);
  float4 out_lo, out_hi;
  widen_pixel_box(lo, hi, &out_lo, &out_hi);
  box_lo[c] = out_lo;
  box_hi[c] = out_hi;
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
