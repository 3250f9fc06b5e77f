/* Clustered shading, part 1 of 3: the clusters' view-space boxes and the
 * lights' view-space spheres (the other parts: light_bvh.cl, cluster_assign.cl).
 *
 *   light_view            world lights -> view-space spheres
 *   cluster_boxes         unique keys -> view-space AABB of each sub-frustum
 *                         (implicit bounds), or
 *   cluster_pixel_boxes   depth + pixel -> cluster map -> view-space AABB of
 *                         each cluster's pixels (explicit bounds); GPU shape:
 *                         cluster_pixel_boxes_wg, then cluster_boxes_finish
 *
 * light_view and cluster_boxes are one work-item per light or cluster with
 * coalesced reads and writes and serve both shapes.
 *
 * Kernel shapes: the kernels without a suffix are the CPU shape (a work-item
 * per screen tile with private state; PoCL runs each as a plain loop); the *_wg
 * kernels are the GPU shape of the same passes (work-groups cooperating
 * through local memory, consecutive work-items on consecutive data) with the
 * same outputs. The host picks one set (ClusterLightAssigner,
 * --kernel-shape); work-group sizes are powers of two it fits to the
 * kernel's limits, at most the *_WG bounds below.
 *
 * Mirrors host/clustered/ClusterGeometry.cpp (no contraction on either side).
 */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#include "common/view_frustum.cl" /* mat_mul, tile_ndc_span, frustum_xy_box, DEPTH_EPS */

__kernel void light_view(__global const PointLight* lights, uint n, CameraParams cam, __global float4* spheres) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const PointLight l = lights[i];
  float4 c = mat_mul(cam.view, (float4)(l.position_radius.xyz, 1.0f));
  c.w = l.position_radius.w;
  spheres[i] = c;
}

/* lo = (x0, y0, z0), hi = (x1, y1, z1); z as positive distance. */
__kernel void cluster_boxes(__global const uint* keys, uint count, CameraParams cam, __global const float* bounds,
                            uint tile, uint x_bits, uint k_bits, __global float4* box_lo, __global float4* box_hi) {
  const uint c = get_global_id(0);
  if (c >= count) return;
  const uint key = keys[c];
  const uint k = key & ((1u << k_bits) - 1u);
  const uint i = (key >> k_bits) & ((1u << x_bits) - 1u);
  const uint j = key >> (k_bits + x_bits);
  const float zmin = k == 0u ? 0.0f : bounds[k] - bounds[k] * DEPTH_EPS;
  const float zmax = bounds[k + 1u] + bounds[k + 1u] * DEPTH_EPS;
  const float4 box = frustum_xy_box(tile_ndc_span(i, tile, cam.width), tile_ndc_span(j, tile, cam.height), zmin,
                                    zmax, cam.proj);
  box_lo[c] = (float4)(box.x, box.z, zmin, 0.0f);
  box_hi[c] = (float4)(box.y, box.w, zmax, 0.0f);
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

/* ============================================================ GPU shape */

#define PIX_WG 256   /* cluster_pixel_boxes_wg: most work-items per tile */
#define PIX_SLOTS 64 /* clusters of a tile reduced in local memory; the rest use global atomics */

/* A float as an int that orders like the float, for atomic_min/max. */
inline int ordered_int(float f) {
  const int i = as_int(f);
  return i >= 0 ? i : i ^ 0x7fffffff;
}
inline float from_ordered_int(int i) { return as_float(i >= 0 ? i : i ^ 0x7fffffff); }
#define ORDERED_INF 0x7f800000          /* ordered_int(+INFINITY) */
#define ORDERED_NEG_INF ((int)0x807fffff) /* ordered_int(-INFINITY) */

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
