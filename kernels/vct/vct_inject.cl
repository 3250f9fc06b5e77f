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
 * compiles none of it, so the option costs nothing when off.
 * VCT_SHADOW_SKIP=1: the march skips runs of samples in empty space and
 * outside the grid, read from the distance volume `occ`
 * (vct_occupancy.cl), and decides exactly as the plain march (0: every
 * sample loads its voxel; the bench's peer and what the twin does). */
#pragma OPENCL FP_CONTRACT OFF
#include "vct/vct_common.cl"
#include "gpu_types.h"
#include "voxel_types.h"
#include "voxel_occupancy.h"
#include "shading_model.h"
#include "hashed/hashed_lookup.cl"

/* The window coordinates of stored voxel i (voxel_types.h, `wrap`: stored
 * at (window + k) mod edge for the corner's lattice index k; the mask takes
 * k mod edge, k = 0 for an unscrolled grid). */
ML_INLINE uint3 window_voxel(uint i, uint edge_log2, uint4 shift) {
  const uint mask = (1u << edge_log2) - 1u;
  return (uint3)(((i & mask) - shift.x) & mask, (((i >> edge_log2) & mask) - shift.y) & mask,
                 ((i >> (2u * edge_log2)) - shift.z) & mask);
}
/* Whether window voxel w lies in one of the n boxes (lo, hi pairs of window
 * coordinates, hi exclusive); every voxel when n is 0. */
ML_INLINE bool in_boxes(uint3 w, __global const uint4* boxes, uint n) {
  if (n == 0u) return true;
  for (uint b = 0; b < n; ++b) {
    const uint4 lo = boxes[2u * b], hi = boxes[2u * b + 1u];
    if (w.x >= lo.x && w.y >= lo.y && w.z >= lo.z && w.x < hi.x && w.y < hi.y && w.z < hi.z) return true;
  }
  return false;
}

typedef struct Surfel {
  float3 albedo, n, p;
} Surfel;

/* False for an empty voxel. Same operations as the twin's resolveVoxel(). */
ML_INLINE bool resolve_voxel(__global const VoxelAccum* accum, uint i, float4 origin_size, uint edge_log2,
                             int4 corner, Surfel* s) {
  const uint4 shift = as_uint4(corner);
  const VoxelAccum a = accum[i];
  if (a.albedo_count[3] == 0u) return false;
  const float denom = (float)a.albedo_count[3] * (float)ML_VOXEL_ALBEDO_SCALE;
  s->albedo = (float3)((float)a.albedo_count[0] / denom, (float)a.albedo_count[1] / denom,
                       (float)a.albedo_count[2] / denom);
  const float nx = (float)a.normal_sum[0], ny = (float)a.normal_sum[1], nz = (float)a.normal_sum[2];
  const float len = sqrt(nx * nx + ny * ny + nz * nz);
  s->n = len > 0.0f ? (float3)(nx / len, ny / len, nz / len) : (float3)(0.0f);
  const uint3 w = window_voxel(i, edge_log2, shift);
  if (corner.w) {
    /* Toroidal: from the lattice index, the same bits wherever the window is. */
    s->p = (float3)(((float)(corner.x + (int)w.x) + 0.5f) * origin_size.w,
                    ((float)(corner.y + (int)w.y) + 0.5f) * origin_size.w,
                    ((float)(corner.z + (int)w.z) + 0.5f) * origin_size.w);
    return true;
  }
  s->p = (float3)(origin_size.x + ((float)w.x + 0.5f) * origin_size.w, origin_size.y + ((float)w.y + 0.5f) * origin_size.w,
                  origin_size.z + ((float)w.z + 0.5f) * origin_size.w);
  return true;
}

/* The level-0 grid the visibility march reads: filled voxels are opaque.
 * occ: its empty-space distance volume (voxel_occupancy.h), read by the
 * skipping march only. */
typedef struct ShadowGrid {
  __global const VoxelAccum* accum;
  __global const uchar* occ;
  float4 origin_size;
  uint edge_log2;
} ShadowGrid;

#if VCT_SHADOWS
/* The march from a = p + n * voxel size (one voxel off the surface, so the
 * voxel does not shadow itself) to the light: d = light - a, `steps` equal
 * parts, steps = ceil(2 * dominant-axis span / voxel size), sample k at the
 * midpoint t = (k + 0.5) / steps of part k. */
typedef struct March {
  float ax, ay, az, dx, dy, dz;
  uint steps;
  float3 rel, inv; /* skipping: origin - a, steps / d (infinite where d = 0) */
} March;

/* Out-parameter, not a returned struct: a struct return becomes an sret
 * (noalias) pointer whose inlining Oclgrind cannot simulate. */
ML_INLINE void march_to(const ShadowGrid* g, const Surfel* s, float3 lp, March* out) {
  const float h = g->origin_size.w;
  March m;
  m.ax = s->p.x + s->n.x * h;
  m.ay = s->p.y + s->n.y * h;
  m.az = s->p.z + s->n.z * h;
  m.dx = lp.x - m.ax;
  m.dy = lp.y - m.ay;
  m.dz = lp.z - m.az;
  const float span = fmax(fabs(m.dx), fmax(fabs(m.dy), fabs(m.dz)));
  m.steps = (uint)ceil(2.0f * span / h);
#if VCT_SHADOW_SKIP
  const float steps = (float)m.steps;
  m.rel = (float3)(g->origin_size.x - m.ax, g->origin_size.y - m.ay, g->origin_size.z - m.az);
  m.inv = (float3)(m.dx == 0.0f ? INFINITY : steps / m.dx, m.dy == 0.0f ? INFINITY : steps / m.dy,
                   m.dz == 0.0f ? INFINITY : steps / m.dz);
#endif
  *out = m;
}

/* Voxel coordinates of sample k, floored but kept in float (no int
 * overflow for far samples). Each is a monotone function of k (t, then
 * a + d * t, then the subtraction, division and floor are all monotone in
 * IEEE arithmetic): non-decreasing along an axis with d > 0, non-increasing
 * with d < 0, constant with d = 0. The skipping march rests on this. */
ML_INLINE float3 march_cell(const ShadowGrid* g, const March* m, uint k) {
  const float t = ((float)k + 0.5f) / (float)m->steps;
  const float h = g->origin_size.w;
  return (float3)(floor((m->ax + m->dx * t - g->origin_size.x) / h), floor((m->ay + m->dy * t - g->origin_size.y) / h),
                  floor((m->az + m->dz * t - g->origin_size.z) / h));
}

ML_INLINE bool cell_outside(float3 v, float edge) {
  return v.x < 0.0f || v.y < 0.0f || v.z < 0.0f || v.x >= edge || v.y >= edge || v.z >= edge;
}

ML_INLINE uint cell_index(float3 v, uint edge_log2) {
  return ((uint)v.z << (2u * edge_log2)) | ((uint)v.y << edge_log2) | (uint)v.x;
}

#if VCT_SHADOW_SKIP
/* An estimate of the last sample index whose cell can still lie in [lo, hi]
 * along one axis (infinite bounds allowed): a + d * (j + 0.5) / steps solved
 * for the box's exit face, with rel = o - a and inv = steps / d precomputed
 * per march. Rounding in it is caught by the caller, which checks the
 * sample it points to. */
ML_INLINE float axis_last(float rel, float inv, float h, float lo, float hi) {
  if (isinf(inv)) return INFINITY;
  const float face = inv > 0.0f ? hi + 1.0f : lo;
  if (isinf(face)) return INFINITY;
  return ceil((rel + face * h) * inv - 0.5f) - 1.0f;
}

ML_INLINE bool cell_in_box(float3 v, float3 lo, float3 hi) {
  return v.x >= lo.x && v.y >= lo.y && v.z >= lo.z && v.x <= hi.x && v.y <= hi.y && v.z <= hi.z;
}

/* Next sample to test after sample k, whose cell lies in the empty box
 * [lo, hi] (voxel coordinates): j + 1 for the estimated last sample j in the
 * box (or the one before it) once its cell is checked to lie in the box:
 * each coordinate is monotone in the sample index, so every sample between k
 * and j then lies in the box too. k + 1 when neither checks out. */
ML_INLINE uint skip_box(const ShadowGrid* g, const March* m, uint k, float3 lo, float3 hi) {
  const float h = g->origin_size.w;
  const float j = fmin(axis_last(m->rel.x, m->inv.x, h, lo.x, hi.x),
                       fmin(axis_last(m->rel.y, m->inv.y, h, lo.y, hi.y), axis_last(m->rel.z, m->inv.z, h, lo.z, hi.z)));
  if (!(j > (float)k)) return k + 1u;
  /* j is a whole number here; clamped to the last sample before the cast. */
  uint jj = j >= (float)(m->steps - 1u) ? m->steps - 1u : (uint)j;
  for (uint tries = 0; tries < 2u && jj > k; ++tries, --jj)
    if (cell_in_box(march_cell(g, m, jj), lo, hi)) return jj + 1u;
  return k + 1u;
}

/* Where the march goes after sample k outside the grid: `steps` when every
 * later sample stays outside (beyond a face and moving away from it), else
 * past the samples beyond that face. */
ML_INLINE uint skip_outside(const ShadowGrid* g, const March* m, uint k, float3 v) {
  const float edge = (float)(1u << g->edge_log2);
  float3 lo = (float3)(-INFINITY), hi = (float3)(INFINITY);
  if (v.x < 0.0f) { if (!(m->dx > 0.0f)) return m->steps; hi.x = -1.0f; }
  else if (v.x >= edge) { if (!(m->dx < 0.0f)) return m->steps; lo.x = edge; }
  else if (v.y < 0.0f) { if (!(m->dy > 0.0f)) return m->steps; hi.y = -1.0f; }
  else if (v.y >= edge) { if (!(m->dy < 0.0f)) return m->steps; lo.y = edge; }
  else if (v.z < 0.0f) { if (!(m->dz > 0.0f)) return m->steps; hi.z = -1.0f; }
  else { if (!(m->dz < 0.0f)) return m->steps; lo.z = edge; }
  return skip_box(g, m, k, lo, hi);
}

/* The plain march's decision, testing fewer samples: a sample whose voxel
 * is d >= 3 voxels from any filled one (the distance volume) is skipped
 * together with the run of samples after it proven to lie in the empty cube
 * of half-width d - 1 around it (at d = 2 the cube saves too few samples to
 * pay for the jump's check; measured), and likewise runs outside the grid; the rest
 * read a byte instead of loading the voxel. *tested counts the samples it
 * looked at. */
ML_INLINE float voxel_visibility(const ShadowGrid* g, const Surfel* s, float3 lp, uint* tested) {
  March m;
  march_to(g, s, lp, &m);
  const float edge = (float)(1u << g->edge_log2);
  uint k = 0;
  while (k < m.steps) {
    ++*tested;
    const float3 v = march_cell(g, &m, k);
    if (cell_outside(v, edge)) {
      k = skip_outside(g, &m, k, v);
      continue;
    }
    const uint d = g->occ[cell_index(v, g->edge_log2)];
    if (d == 0u) return 0.0f;
    const float r = (float)(d - 1u);
    k = d <= 2u ? k + 1u : skip_box(g, &m, k, v - r, v + r);
  }
  return 1.0f;
}
#else
/* Hard visibility of light position `lp` from surfel `s`: 0 when a filled
 * level-0 voxel (opacity 1, so a soft product of (1 - opacity) would give the
 * same) lies on a sample of the march (march_to()): samples at most half a
 * voxel apart along every axis, so no voxel the segment crosses deeply is
 * skipped, and the last stops within half a voxel of the light. Samples
 * outside the grid are empty. The plain march: every sample loads its voxel.
 * Same operations as the twin's voxelVisibility(). */
ML_INLINE float voxel_visibility(const ShadowGrid* g, const Surfel* s, float3 lp, uint* tested) {
  March m;
  march_to(g, s, lp, &m);
  const float edge = (float)(1u << g->edge_log2);
  for (uint k = 0; k < m.steps; ++k) {
    ++*tested;
    const float3 v = march_cell(g, &m, k);
    if (cell_outside(v, edge)) continue;
    if (g->accum[cell_index(v, g->edge_log2)].albedo_count[3] != 0u) return 0.0f;
  }
  return 1.0f;
}
#endif
#endif

ML_INLINE float3 add_light(float3 acc, const Surfel* s, __global const PointLight* l, const ShadowGrid* g) {
  const float4 pr = l->position_radius, c = l->color;
  float w = ml_light_weight(pr.x, pr.y, pr.z, pr.w, s->p.x, s->p.y, s->p.z, s->n.x, s->n.y, s->n.z);
#if VCT_SHADOWS
  uint tested = 0;
  if (w > 0.0f) w = w * voxel_visibility(g, s, pr.xyz, &tested);
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
ML_INLINE float4 inject_voxel(__global const VoxelAccum* accum, __global const uchar* occ, uint i, float4 origin_size,
                              uint edge_log2, int4 corner, __global const PointLight* lights, uint n_lights,
                              const HsBuffers* hb) {
  Surfel s;
  if (!resolve_voxel(accum, i, origin_size, edge_log2, corner, &s)) return (float4)(0.0f);
  const ShadowGrid g = {accum, occ, origin_size, edge_log2};
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

/* occ: the distance volume of accum (read with VCT_SHADOW_SKIP only).
 * corner: a toroidal grid's lattice corner k (xyz) and 1 (w), else 0
 * (voxel_corner(); window voxel v is stored at (v + k) mod edge); boxes, n_boxes:
 * only the voxels in these window boxes are written (a scrolled cascade
 * level's new slabs), every voxel when n_boxes is 0. */
__kernel VCT_ATTR void inject_brute(__global const VoxelAccum* accum, __global const uchar* occ, __global float4* out,
                                    float4 origin_size, uint edge_log2, int4 corner, __global const uint4* boxes,
                                    uint n_boxes, uint n, uint chunk, __global const PointLight* lights,
                                    uint n_lights) {
  uint b, e;
  item_range(n, chunk, &b, &e);
  for (uint i = b; i < e; ++i)
    if (in_boxes(window_voxel(i, edge_log2, as_uint4(corner)), boxes, n_boxes))
      out[i] = inject_voxel(accum, occ, i, origin_size, edge_log2, corner, lights, n_lights, 0);
}

__kernel VCT_ATTR void inject_hashed(__global const VoxelAccum* accum, __global const uchar* occ, __global float4* out,
                                     float4 origin_size, uint edge_log2, int4 corner, __global const uint4* boxes,
                                     uint n_boxes, uint n, uint chunk, __global const PointLight* lights,
                                     __global const uint* header, __global const uint* offsets,
                                     __global const uint2* desc, __global const uint4* data,
                                     __global const uint* list) {
  const HsBuffers hb = {header, offsets, desc, data, list};
  uint b, e;
  item_range(n, chunk, &b, &e);
  for (uint i = b; i < e; ++i)
    if (in_boxes(window_voxel(i, edge_log2, as_uint4(corner)), boxes, n_boxes))
      out[i] = inject_voxel(accum, occ, i, origin_size, edge_log2, corner, lights, 0u, &hb);
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

#if VCT_SHADOWS
/* Tests: per query q, the march from surfel (position pn[2q].xyz, unit
 * normal pn[2q + 1].xyz) to light position lp[q].xyz: (visible, samples
 * tested). One query per work-item. */
__kernel void visibility_probe(__global const VoxelAccum* accum, __global const uchar* occ, float4 origin_size,
                               uint edge_log2, __global const float4* pn, __global const float4* lp, uint n,
                               __global uint2* out) {
  const uint q = get_global_id(0);
  if (q >= n) return;
  const ShadowGrid g = {accum, occ, origin_size, edge_log2};
  Surfel s;
  s.albedo = (float3)(0.0f);
  s.p = pn[2u * q].xyz;
  s.n = pn[2u * q + 1u].xyz;
  uint tested = 0;
  const float v = voxel_visibility(&g, &s, lp[q].xyz, &tested);
  out[q] = (uint2)(v > 0.0f ? 1u : 0u, tested);
}
#endif
