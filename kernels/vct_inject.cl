/* Resolve + light injection (voxel cone tracing), per level-0 voxel of the
 * grid (edge 1 << edge_log2, corner and voxel size in origin_size):
 *   count = 0: (0, 0, 0, 0), empty;
 *   else albedo = sum / (count * 255), n = normalized normal sum (zero if
 *   the sum is zero), and the voxel's outgoing diffuse radiance
 *   albedo * ML_SHADE_DIRECT * sum_i I_i * w_i at the voxel centre
 *   (shading_model.h: the renderer's model without its ambient term), with
 *   opacity 1: (radiance, 1), premultiplied trivially.
 * inject_brute sums over every light (the reference); inject_hashed over the
 * hashed structure's list at the voxel centre (hashed_lookup.cl), in list
 * order. Shapes as in vct_common.cl. The C++ twin is host/vct/InjectTwin.hpp.
 * VCT_SHADOWS=1 (--vct-shadows voxel): each light's term is multiplied by its
 * visibility through level-0 opacity (voxel_visibility()); 0 or undefined
 * compiles none of it, so the option costs nothing when off. */
#pragma OPENCL FP_CONTRACT OFF
#include "vct_common.cl"
#include "gpu_types.h"
#include "voxel_types.h"
#include "shading_model.h"
#include "hashed_lookup.cl"

typedef struct Surfel {
  float3 albedo, n, p;
} Surfel;

/* False for an empty voxel. Same operations as the twin's resolveVoxel(). */
ML_INLINE bool resolve_voxel(__global const VoxelAccum* accum, uint i, float4 origin_size, uint edge_log2,
                             Surfel* s) {
  const VoxelAccum a = accum[i];
  if (a.albedo_count[3] == 0u) return false;
  const float denom = (float)a.albedo_count[3] * (float)ML_VOXEL_ALBEDO_SCALE;
  s->albedo = (float3)((float)a.albedo_count[0] / denom, (float)a.albedo_count[1] / denom,
                       (float)a.albedo_count[2] / denom);
  const float nx = (float)a.normal_sum[0], ny = (float)a.normal_sum[1], nz = (float)a.normal_sum[2];
  const float len = sqrt(nx * nx + ny * ny + nz * nz);
  s->n = len > 0.0f ? (float3)(nx / len, ny / len, nz / len) : (float3)(0.0f);
  const uint mask = (1u << edge_log2) - 1u;
  const uint x = i & mask, y = (i >> edge_log2) & mask, z = i >> (2u * edge_log2);
  s->p = (float3)(origin_size.x + ((float)x + 0.5f) * origin_size.w, origin_size.y + ((float)y + 0.5f) * origin_size.w,
                  origin_size.z + ((float)z + 0.5f) * origin_size.w);
  return true;
}

/* The level-0 grid the visibility march reads: filled voxels are opaque. */
typedef struct VoxelOccupancy {
  __global const VoxelAccum* accum;
  float4 origin_size;
  uint edge_log2;
} VoxelOccupancy;

#if VCT_SHADOWS
/* Hard visibility of light position `lp` from surfel `s`: 0 when a filled
 * level-0 voxel (opacity 1, so a soft product of (1 - opacity) would give the
 * same) lies on the segment from a = p + n * voxel size (one voxel off the
 * surface, so the voxel does not shadow itself) to the light, sampled at the
 * midpoints of `steps` equal parts, steps = ceil(2 * dominant-axis span /
 * voxel size): at most half a voxel apart along every axis, so no voxel the
 * segment crosses deeply is skipped, and the last sample stops within half a
 * voxel of the light. Samples outside the grid are empty. Same operations as
 * the twin's voxelVisibility(). */
ML_INLINE float voxel_visibility(const VoxelOccupancy* g, const Surfel* s, float3 lp) {
  const float h = g->origin_size.w;
  const float ax = s->p.x + s->n.x * h, ay = s->p.y + s->n.y * h, az = s->p.z + s->n.z * h;
  const float dx = lp.x - ax, dy = lp.y - ay, dz = lp.z - az;
  const float span = fmax(fabs(dx), fmax(fabs(dy), fabs(dz)));
  const uint steps = (uint)ceil(2.0f * span / h);
  const int edge = 1 << g->edge_log2;
  for (uint k = 0; k < steps; ++k) {
    const float t = ((float)k + 0.5f) / (float)steps;
    const int x = (int)floor((ax + dx * t - g->origin_size.x) / h);
    const int y = (int)floor((ay + dy * t - g->origin_size.y) / h);
    const int z = (int)floor((az + dz * t - g->origin_size.z) / h);
    if (x < 0 || y < 0 || z < 0 || x >= edge || y >= edge || z >= edge) continue;
    const uint i = ((uint)z << (2u * g->edge_log2)) | ((uint)y << g->edge_log2) | (uint)x;
    if (g->accum[i].albedo_count[3] != 0u) return 0.0f;
  }
  return 1.0f;
}
#endif

ML_INLINE float3 add_light(float3 acc, const Surfel* s, __global const PointLight* l, const VoxelOccupancy* g) {
  const float4 pr = l->position_radius, c = l->color;
  float w = ml_light_weight(pr.x, pr.y, pr.z, pr.w, s->p.x, s->p.y, s->p.z, s->n.x, s->n.y, s->n.z);
#if VCT_SHADOWS
  if (w > 0.0f) w = w * voxel_visibility(g, s, pr.xyz);
#else
  (void)g;
#endif
  return (float3)(acc.x + c.x * w, acc.y + c.y * w, acc.z + c.z * w);
}

ML_INLINE float4 lit(const Surfel* s, float3 acc) {
  return (float4)(s->albedo.x * (ML_SHADE_DIRECT * acc.x), s->albedo.y * (ML_SHADE_DIRECT * acc.y),
                  s->albedo.z * (ML_SHADE_DIRECT * acc.z), 1.0f);
}

/* One voxel's injected radiance: summed over every light (hb null: brute
 * force) or over the hashed list at the voxel centre, in list order. Both
 * kernels go through here so that the two sums differ only in their lights. */
ML_INLINE float4 inject_voxel(__global const VoxelAccum* accum, uint i, float4 origin_size, uint edge_log2,
                              __global const PointLight* lights, uint n_lights, const HsBuffers* hb) {
  Surfel s;
  if (!resolve_voxel(accum, i, origin_size, edge_log2, &s)) return (float4)(0.0f);
  const VoxelOccupancy g = {accum, origin_size, edge_log2};
  float3 acc = (float3)(0.0f);
  if (hb) {
    HsList hl = hs_list_for(hb, s.p);
    while (hl.offset < hl.end) {
      uint light;
      if (hs_next(hb, &hl, &light)) acc = add_light(acc, &s, lights + light, &g);
    }
  } else {
    for (uint l = 0; l < n_lights; ++l) acc = add_light(acc, &s, lights + l, &g);
  }
  return lit(&s, acc);
}

__kernel VCT_ATTR void inject_brute(__global const VoxelAccum* accum, __global float4* out, float4 origin_size,
                                    uint edge_log2, uint n, uint chunk, __global const PointLight* lights,
                                    uint n_lights) {
  uint b, e;
  item_range(n, chunk, &b, &e);
  for (uint i = b; i < e; ++i) out[i] = inject_voxel(accum, i, origin_size, edge_log2, lights, n_lights, 0);
}

__kernel VCT_ATTR void inject_hashed(__global const VoxelAccum* accum, __global float4* out, float4 origin_size,
                                     uint edge_log2, uint n, uint chunk, __global const PointLight* lights,
                                     __global const uint* header, __global const uint* offsets,
                                     __global const uint2* desc, __global const uint4* data,
                                     __global const uint* list) {
  const HsBuffers hb = {header, offsets, desc, data, list};
  uint b, e;
  item_range(n, chunk, &b, &e);
  for (uint i = b; i < e; ++i) out[i] = inject_voxel(accum, i, origin_size, edge_log2, lights, 0u, &hb);
}

/* Tests: the lookup's range (offset, count) and octant for each point. */
__kernel void hashed_lookup_probe(__global const float4* points, uint n, __global uint4* out,
                                  __global const uint* header, __global const uint* offsets,
                                  __global const uint2* desc, __global const uint4* data, __global const uint* list) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const HsBuffers hb = {header, offsets, desc, data, list};
  const HsList l = hs_list_for(&hb, points[i].xyz);
  const uint octant = l.octant_bit ? 31u - clz(l.octant_bit) - 24u : 0u;
  out[i] = (uint4)(l.offset, l.end - l.offset, octant, 0u);
}
