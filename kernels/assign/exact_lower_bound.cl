/* The exact lower bound of light evaluations: for every covered pixel, the
 * number of lights whose sphere strictly contains the surface point
 * (|L - P|^2 < r^2), P reconstructed from the frame's depth buffer. It is
 * computed here once per counted frame, the same way for every technique.
 *
 *   exact_lower_bound  one work-item per pixel: window_to_world, then per
 *                      grid level the lights listed in P's cell, those from
 *                      the `first`th to before the (first + span)th of the
 *                      cell's list; launches with first > 0 add to counts
 *
 * Why slices: llvmpipe (Mesa rusticl) ends a work-item's loops after 65,535
 * iterations in total, all loops together (tests/driver/driver_loop_cap_test.cpp),
 * so a pixel inside 66,000 spheres would count 65,535. The host
 * (ExactLowerBound::count) keeps level_count * (span + 1) under that and
 * launches once per slice of the longest list: once, unless a list is long.
 *
 * The grid (host/assign/ExactLowerBound.cpp) lists each light in every cell
 * that its sphere's box, widened for rounding, overlaps, so no light whose
 * sphere contains P is missed; the test below is the exact predicate.
 * The C++ twin (ml::boundAtPixel) and the shaders' in-range count
 * (gl/shaders/common/common.glsl, shading.glsl) make the same operations in the same
 * order, hence no contraction into fused multiply-adds. */
#include "gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

/* Column-major 4x4 times a vector, summed column by column as GLSL does. */
inline float4 bound_mat_mul(__global const float* m, float4 v) {
  return (float4)(m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12] * v.w,
                  m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13] * v.w,
                  m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14] * v.w,
                  m[3] * v.x + m[7] * v.y + m[11] * v.z + m[15] * v.w);
}

/* Depth of pixel (x, y) (window space, reversed-Z: depth_convention.h) ->
 * world position; false for background. The one place depth becomes a
 * position; the same operations as windowToView in gl/shaders/common/common.glsl. */
inline bool window_to_world(float depth, uint x, uint y, __global const BoundParams* p, float3* world) {
  if (is_sky_depth(depth)) return false;
  const float z = depth_to_distance(depth, p->proj[10], p->proj[14]);
  const float ndc_x = ((float)x + 0.5f) / (float)p->width * 2.0f - 1.0f;
  const float ndc_y = ((float)y + 0.5f) / (float)p->height * 2.0f - 1.0f;
  const float vx = (ndc_x + p->proj[8]) / p->proj[0];
  const float vy = (ndc_y + p->proj[9]) / p->proj[5];
  const float4 view = (float4)(z * vx, z * vy, -z, 1.0f);
  *world = bound_mat_mul(p->inv_view, view).xyz;
  return true;
}

/* Lights whose sphere contains P, over the slice [first, first + span) of
 * every level's list of P's cell. */
inline uint lights_containing(float3 P, __global const BoundGridLevel* levels, uint level_count,
                              __global const uint* cell_start, __global const uint* entries,
                              __global const float4* spheres, uint first, uint span) {
  uint n = 0;
  for (uint l = 0; l < level_count; ++l) {
    const BoundGridLevel g = levels[l];
    const float s = g.origin_cell[3];
    const float qx = floor((P.x - g.origin_cell[0]) / s);
    const float qy = floor((P.y - g.origin_cell[1]) / s);
    const float qz = floor((P.z - g.origin_cell[2]) / s);
    if (!(qx >= 0.0f && qx < (float)g.dims[0] && qy >= 0.0f && qy < (float)g.dims[1] && qz >= 0.0f &&
          qz < (float)g.dims[2]))
      continue;
    const uint c = g.dims[3] + (uint)qx + g.dims[0] * ((uint)qy + g.dims[1] * (uint)qz);
    const uint begin = cell_start[c], length = cell_start[c + 1] - begin;
    if (first >= length) continue;
    const uint end = begin + (length - first > span ? first + span : length);
    for (uint e = begin + first; e < end; ++e) {
      const float4 L = spheres[entries[e]];
      const float dx = L.x - P.x, dy = L.y - P.y, dz = L.z - P.z;
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < L.w * L.w) ++n;
    }
  }
  return n;
}

/* counts[y * width + x]: the pixel's bound (0 for background), summed over
 * the launches of slices first = 0, span, 2 * span, ... */
__kernel void exact_lower_bound(__global const float* depth, __global const BoundParams* params,
                                __global const BoundGridLevel* levels, __global const uint* cell_start,
                                __global const uint* entries, __global const float4* spheres,
                                __global uint* counts, uint first, uint span) {
  const uint i = get_global_id(0);
  const uint width = params->width;
  if (i >= width * params->height) return;
  float3 P;
  const uint n = window_to_world(depth[i], i % width, i / width, params, &P)
                     ? lights_containing(P, levels, params->level_count, cell_start, entries, spheres, first, span)
                     : 0u;
  counts[i] = first == 0 ? n : counts[i] + n;
}
