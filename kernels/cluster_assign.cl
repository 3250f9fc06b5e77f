/* Clustered shading: lights -> unique clusters.
 *
 *   light_view            world lights -> view-space spheres
 *   cluster_boxes         unique keys -> view-space AABB of each sub-frustum
 *   brute_count/fill      per cluster, every light (the reference)
 *   light_morton          30-bit Morton code of each light's quantized position
 *   (radix sort of the codes, light indices as payload)
 *   bvh_leaves            nodes over 32 consecutive sorted lights
 *   bvh_level             nodes over 32 consecutive nodes of the level below
 *   bvh_count/fill        per cluster, walk the BVH from its top level
 *
 * Lists are built count -> scan -> fill: the fill pass redoes the tests and
 * writes the cluster's own range, so no atomics and nothing can overflow. One
 * work-item per cluster with private state (the CPU shape; see the PoCL
 * notes). The leaf test is the brute-force test, and node boxes are padded
 * beyond the sphere bounds, so BVH lists equal brute-force lists as sets.
 * Mirrors host/clustered/ClusterGeometry.cpp (no contraction on either side).
 */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#define BVH_BRANCH 32u
/* Stack of pending nodes: at most BVH_BRANCH per level plus the top level. */
#define BVH_STACK 256
#define DEPTH_EPS 1e-4f

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

inline bool sphere_hits_box(float4 s, float4 lo, float4 hi) {
  const float d = -s.z;
  const float dx = s.x - clamp(s.x, lo.x, hi.x), dy = s.y - clamp(s.y, lo.y, hi.y), dz = d - clamp(d, lo.z, hi.z);
  return dx * dx + dy * dy + dz * dz <= s.w * s.w * (1.0f + 4.0f * DEPTH_EPS);
}

/* ------------------------------------------------------------ brute force */

__kernel void brute_assign(__global const float4* spheres, uint n, __global const float4* box_lo,
                           __global const float4* box_hi, uint count, __global uint* counts,
                           __global const uint* offsets, __global uint* indices, uint fill) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const float4 lo = box_lo[c], hi = box_hi[c];
  uint m = 0;
  const uint base = fill ? offsets[c] : 0u;
  for (uint i = 0; i < n; ++i)
    if (sphere_hits_box(spheres[i], lo, hi)) {
      if (fill) indices[base + m] = i;
      ++m;
    }
  if (!fill) counts[c] = m;
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

/* Quantized in the view-space cube [lo, lo + extent]; positions outside
 * clamp, which only costs tree quality, never correctness. */
__kernel void light_morton(__global const float4* spheres, uint n, float4 lo, float inv_extent,
                           __global uint* codes, __global uint* ids) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 s = spheres[i];
  const float3 t = clamp((s.xyz - lo.xyz) * inv_extent, 0.0f, 1.0f) * 1023.0f;
  codes[i] = spread10((uint)t.x) | (spread10((uint)t.y) << 1) | (spread10((uint)t.z) << 2);
  ids[i] = i;
}

/* Sphere bounds padded by 1e-3 r: a sphere that passes the leaf test
 * (which tolerates 4 * DEPTH_EPS of r^2) always overlaps its box. The box z
 * is stored as positive distance like the cluster boxes. */
__kernel void bvh_leaves(__global const float4* spheres, __global const uint* ids, uint n,
                         __global float4* sorted, __global uint* sorted_ids, __global float4* node_lo,
                         __global float4* node_hi) {
  const uint node = get_global_id(0);
  const uint first = node * BVH_BRANCH;
  if (first >= n) return;
  const uint last = min(first + BVH_BRANCH, n);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = first; i < last; ++i) {
    const uint id = ids[i];
    const float4 s = spheres[id];
    sorted[i] = s;
    sorted_ids[i] = id;
    const float r = s.w * 1.001f + 1e-6f;
    const float4 p = (float4)(s.x, s.y, -s.z, 0.0f);
    lo = fmin(lo, p - r);
    hi = fmax(hi, p + r);
  }
  node_lo[node] = lo;
  node_hi[node] = hi;
}

/* Children at [child_start, child_start + n_children), parents from parent_start. */
__kernel void bvh_level(__global float4* node_lo, __global float4* node_hi, uint child_start, uint n_children,
                        uint parent_start) {
  const uint node = get_global_id(0);
  const uint first = node * BVH_BRANCH;
  if (first >= n_children) return;
  const uint last = min(first + BVH_BRANCH, n_children);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint i = first; i < last; ++i) {
    lo = fmin(lo, node_lo[child_start + i]);
    hi = fmax(hi, node_hi[child_start + i]);
  }
  node_lo[parent_start + node] = lo;
  node_hi[parent_start + node] = hi;
}

inline bool boxes_overlap(float4 alo, float4 ahi, float4 blo, float4 bhi) {
  return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y && alo.z <= bhi.z && blo.z <= ahi.z;
}

/* Nodes of all levels in one array; level l starts at level_start[l] (level 0
 * = leaves) and has level_count[l] nodes; `levels` levels, the top one has at
 * most BVH_BRANCH nodes. Stack entries: level << 27 | node. */
__kernel void bvh_assign(__global const float4* sorted, __global const uint* sorted_ids, uint n,
                         __global const float4* node_lo, __global const float4* node_hi,
                         __global const uint* level_start, __global const uint* level_count, uint levels,
                         __global const float4* box_lo, __global const float4* box_hi, uint count,
                         __global uint* counts, __global const uint* offsets, __global uint* indices, uint fill) {
  const uint c = get_global_id(0);
  if (c >= count || n == 0u) {
    if (c < count && !fill) counts[c] = 0u;
    return;
  }
  const float4 lo = box_lo[c], hi = box_hi[c];
  uint stack[BVH_STACK];
  uint sp = 0;
  const uint top = levels - 1u;
  for (uint t = level_count[top]; t > 0u; --t) stack[sp++] = (top << 27) | (t - 1u);
  uint m = 0;
  const uint base = fill ? offsets[c] : 0u;
  while (sp > 0u) {
    const uint e = stack[--sp];
    const uint l = e >> 27, node = e & 0x7ffffffu;
    const uint g = level_start[l] + node;
    if (!boxes_overlap(node_lo[g], node_hi[g], lo, hi)) continue;
    const uint first = node * BVH_BRANCH;
    if (l == 0u) {
      const uint last = min(first + BVH_BRANCH, n);
      for (uint i = first; i < last; ++i)
        if (sphere_hits_box(sorted[i], lo, hi)) {
          if (fill) indices[base + m] = sorted_ids[i];
          ++m;
        }
    } else {
      const uint last = min(first + BVH_BRANCH, level_count[l - 1u]);
      for (uint k = last; k > first; --k) stack[sp++] = ((l - 1u) << 27) | (k - 1u);
    }
  }
  if (!fill) counts[c] = m;
}
