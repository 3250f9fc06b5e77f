/* Tiled shading (forward+ / tiled deferred) light culling.
 *
 *   tile_depth_bounds*   depth buffer -> per-tile [min, max] linear view depth
 *                        and a 32-bin 2.5D depth mask (Harada's)
 *   light_rects          per light: screen tile rectangle, hit-mask size
 *   (scan of mask sizes -> per-light mask offsets)
 *   cull_mark            per light: test each tile of its rectangle once;
 *                        set the tile's bit in the light's mask, counts[t]++
 *   (scan of counts -> tile offsets and the list total)
 *   cull_scatter         per light: indices[offsets[t] + slot] for its set bits
 *
 * Light-centric: each work-item walks one light's screen rectangle, so the
 * cost is the lights' covered tiles, not lights x tiles, and the culling math
 * runs once per (light, tile). That is the CPU shape (PoCL runs a work-item as
 * a plain loop). The GPU shape (cull_mark_wg, cull_scatter_wg) spreads the
 * same (light, tile) pairs over one work-item each, a light found from its
 * hit-mask word, so that a light covering the screen does not serialize one
 * work-item while the others idle; tile_depth_bounds_wg gives each tile a
 * work-group. light_rects and write_grid are one work-item per light or
 * tile with coalesced reads and writes and serve both shapes. Lists are built by count -> scan -> fill and
 * cannot overflow: the host sizes the index list from the scan total. Order
 * within a tile list follows atomics.
 *
 * Defines: TILE_SIZE (pixels), DEPTH_MODE (0 none, 1 min/max, 2 2.5D mask).
 */
#include "gpu_types.h"

/* The C++ reference (host/tiled/TileGeometry.cpp) must reach bit-identical
 * decisions, so no fused multiply-adds that the host code would not make. */
#pragma OPENCL FP_CONTRACT OFF

#define DEPTH_NONE 0
#define DEPTH_MINMAX 1
#define DEPTH_MASK 2

/* Column-major 4x4 (glm): element (row r, col c) is m[c * 4 + r]. */
inline float4 mat_mul(const float* m, float4 v) {
  return (float4)(m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12] * v.w,
                  m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13] * v.w,
                  m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14] * v.w,
                  m[3] * v.x + m[7] * v.y + m[11] * v.z + m[15] * v.w);
}
inline float4 mat_row(const float* m, int r) { return (float4)(m[r], m[4 + r], m[8 + r], m[12 + r]); }

/* ---------------------------------------------------------------- bounds */

/* Widening of the tile depth range (relative): the kernel and the shader
 * reconstruct depth along different float paths. */
#define DEPTH_EPS 1e-4f

inline uint bin_of(float z, float zmin, float inv_range) {
  int b = (int)((z - zmin) * inv_range * 32.0f);
  return (uint)clamp(b, 0, 31);
}

/* Tile record: (zmin, zmax) widened for the range test, then the exact zmin
 * and 1/(zmax - zmin) that the mask bins were computed with. Empty tile:
 * zmin > zmax. */
inline float4 widen(float zmin, float zmax) {
  if (zmin > zmax) return (float4)(INFINITY, -INFINITY, 0.0f, 0.0f);
  return (float4)(zmin - zmin * DEPTH_EPS, zmax + zmax * DEPTH_EPS, zmin, 1.0f / fmax(zmax - zmin, 1e-20f));
}

/* CPU shape: one work-item per tile walks its pixels. */
__kernel void tile_depth_bounds(__global const float* depth, CameraParams cam, uint tiles_x, uint tiles_y,
                                __global float4* bounds, __global uint* masks) {
  const uint t = get_global_id(0);
  if (t >= tiles_x * tiles_y) return;
  const uint ty = t / tiles_x, tx = t - ty * tiles_x; /* no `%`: see tile_minmax in reduce.cl */
  const uint x0 = tx * TILE_SIZE, y0 = ty * TILE_SIZE;
  const uint x1 = min(x0 + TILE_SIZE, cam.width), y1 = min(y0 + TILE_SIZE, cam.height);
  float zmin = INFINITY, zmax = -INFINITY;
  for (uint y = y0; y < y1; ++y)
    for (uint x = x0; x < x1; ++x) {
      const float d = depth[y * cam.width + x];
      if (is_sky_depth(d)) continue;
      const float z = linear_depth(d, &cam);
      zmin = fmin(zmin, z);
      zmax = fmax(zmax, z);
    }
  uint mask = 0;
#if DEPTH_MODE == DEPTH_MASK
  if (zmin <= zmax) {
    const float inv = 1.0f / fmax(zmax - zmin, 1e-20f);
    for (uint y = y0; y < y1; ++y)
      for (uint x = x0; x < x1; ++x) {
        const float d = depth[y * cam.width + x];
        if (!is_sky_depth(d)) mask |= 1u << bin_of(linear_depth(d, &cam), zmin, inv);
      }
  }
#endif
  bounds[t] = widen(zmin, zmax);
  masks[t] = mask;
}

/* GPU shape: one work-group (TILE_SIZE x TILE_SIZE work-items, or fewer
 * that stride) per tile, local atomics on the float bits (positive floats
 * order like their uint bits). */
__kernel void tile_depth_bounds_wg(__global const float* depth, CameraParams cam, uint tiles_x, uint tiles_y,
                                   __global float4* bounds, __global uint* masks) {
  __local uint lmin, lmax, lmask;
  const uint t = get_group_id(0);
  const uint lid = get_local_id(0), lsize = get_local_size(0);
  if (lid == 0) {
    lmin = as_uint(INFINITY);
    lmax = 0u;
    lmask = 0u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint ty = t / tiles_x, tx = t - ty * tiles_x; /* no `%`: see tile_minmax in reduce.cl */
  const uint x0 = tx * TILE_SIZE, y0 = ty * TILE_SIZE;
  const uint w = min((uint)TILE_SIZE, cam.width - x0), h = min((uint)TILE_SIZE, cam.height - y0);
  for (uint i = lid; i < w * h; i += lsize) {
    const uint row = i / w;
    const float d = depth[(y0 + row) * cam.width + x0 + (i - row * w)];
    if (!is_sky_depth(d)) {
      const uint z = as_uint(linear_depth(d, &cam));
      atomic_min(&lmin, z);
      atomic_max(&lmax, z);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  float zmin = as_float(lmin), zmax = lmax ? as_float(lmax) : -INFINITY;
#if DEPTH_MODE == DEPTH_MASK
  if (zmin <= zmax) {
    const float inv = 1.0f / fmax(zmax - zmin, 1e-20f);
    uint mask = 0;
    for (uint i = lid; i < w * h; i += lsize) {
      const uint row = i / w;
      const float d = depth[(y0 + row) * cam.width + x0 + (i - row * w)];
      if (!is_sky_depth(d)) mask |= 1u << bin_of(linear_depth(d, &cam), zmin, inv);
    }
    atomic_or(&lmask, mask);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#endif
  if (lid == 0) {
    bounds[t] = widen(zmin, zmax);
    masks[t] = lmask;
  }
}

/* ---------------------------------------------------------------- culling */

typedef struct {
  float4 center;  /* view space, w = radius */
  int tx0, ty0, tx1, ty1;
} LightRect;

/* Screen rectangle of tiles the sphere may touch; empty (tx0 > tx1) if none. */
inline LightRect light_rect(PointLight l, const CameraParams* cam, uint tiles_x, uint tiles_y) {
  LightRect lr;
  const float r = l.position_radius.w;
  float4 c = mat_mul(cam->view, (float4)(l.position_radius.xyz, 1.0f));
  c.w = r;
  lr.center = c;
  lr.tx0 = 0;
  lr.ty0 = 0;
  lr.tx1 = (int)tiles_x - 1;
  lr.ty1 = (int)tiles_y - 1;
  if (c.z - r > -cam->near_plane || -c.z - r > cam->far_plane) { /* wholly in front of near or beyond far */
    lr.tx0 = 1;
    lr.tx1 = 0;
    return lr;
  }
  if (c.z + r > -cam->near_plane) return lr; /* straddles the near plane: whole screen, planes decide */
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  for (int i = 0; i < 8; ++i) {
    const float4 corner = (float4)(c.x + ((i & 1) ? r : -r), c.y + ((i & 2) ? r : -r), c.z + ((i & 4) ? r : -r), 1.0f);
    const float4 clip = mat_mul(cam->proj, corner);
    const float2 ndc = clip.xy / clip.w;
    lo = fmin(lo, ndc);
    hi = fmax(hi, ndc);
  }
  if (hi.x < -1.0f || hi.y < -1.0f || lo.x > 1.0f || lo.y > 1.0f) {
    lr.tx0 = 1;
    lr.tx1 = 0;
    return lr;
  }
  const float2 size = (float2)((float)cam->width, (float)cam->height);
  const float2 p0 = (clamp(lo, -1.0f, 1.0f) * 0.5f + 0.5f) * size;
  const float2 p1 = (clamp(hi, -1.0f, 1.0f) * 0.5f + 0.5f) * size;
  lr.tx0 = clamp((int)floor(p0.x / TILE_SIZE), 0, (int)tiles_x - 1);
  lr.ty0 = clamp((int)floor(p0.y / TILE_SIZE), 0, (int)tiles_y - 1);
  lr.tx1 = clamp((int)floor(p1.x / TILE_SIZE), 0, (int)tiles_x - 1);
  lr.ty1 = clamp((int)floor(p1.y / TILE_SIZE), 0, (int)tiles_y - 1);
  return lr;
}

/* Signed distance test of the sphere against the plane `p` (inside: >= 0). */
inline bool sphere_inside_plane(float4 p, float4 c) {
  return p.x * c.x + p.y * c.y + p.z * c.z + p.w > -c.w * sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}

/* View-space x (or y) of the ray through ndc `n` at distance d: the inverse of
 * ndc = (P00 x + P20 z) / -z for a perspective projection. */
inline float view_coord(float n, float d, float p_diag, float p_off) { return d * (n + p_off) / p_diag; }

/* Sphere against the view-space AABB of the tile's frustum between its
 * depth bounds: removes the false positives of plane tests near corners. */
inline bool sphere_hits_tile_box(float4 c, float xl, float xr, float yb, float yt, float zmin, float zmax,
                                 const CameraParams* cam) {
  const float p00 = cam->proj[0], p20 = cam->proj[8], p11 = cam->proj[5], p21 = cam->proj[9];
  const float x0 = fmin(fmin(view_coord(xl, zmin, p00, p20), view_coord(xl, zmax, p00, p20)),
                        fmin(view_coord(xr, zmin, p00, p20), view_coord(xr, zmax, p00, p20)));
  const float x1 = fmax(fmax(view_coord(xl, zmin, p00, p20), view_coord(xl, zmax, p00, p20)),
                        fmax(view_coord(xr, zmin, p00, p20), view_coord(xr, zmax, p00, p20)));
  const float y0 = fmin(fmin(view_coord(yb, zmin, p11, p21), view_coord(yb, zmax, p11, p21)),
                        fmin(view_coord(yt, zmin, p11, p21), view_coord(yt, zmax, p11, p21)));
  const float y1 = fmax(fmax(view_coord(yb, zmin, p11, p21), view_coord(yb, zmax, p11, p21)),
                        fmax(view_coord(yt, zmin, p11, p21), view_coord(yt, zmax, p11, p21)));
  const float dx = c.x - clamp(c.x, x0, x1), dy = c.y - clamp(c.y, y0, y1), dz = -c.z - clamp(-c.z, zmin, zmax);
  return dx * dx + dy * dy + dz * dz <= c.w * c.w * (1.0f + 4.0f * DEPTH_EPS);
}

/* Does the sphere reach any shaded point of tile (tx, ty)? Conservative.
 * Always inlined: as a call, LLVM passes `undef` for the argument a depth mode
 * does not read, and Oclgrind 21.10's uninitialized-value checker crashes on
 * it (scripts/oclgrind.sh). */
__attribute__((always_inline)) inline bool light_hits_tile(const LightRect* lr, int tx, int ty, const CameraParams* cam,
                            __global const float4* bounds, __global const uint* masks, uint tiles_x) {
  const uint t = (uint)ty * tiles_x + (uint)tx;
#if DEPTH_MODE != DEPTH_NONE
  const float4 zb = bounds[t];
  if (zb.x > zb.y) return false; /* no geometry in the tile */
  const float lz = -lr->center.z, r = lr->center.w;
  if (lz + r < zb.x || lz - r > zb.y) return false;
#if DEPTH_MODE == DEPTH_MASK
  {
    /* The light's depth range is widened like the tile's, so a point on a bin
     * edge cannot fall between the two roundings. */
    const uint b0 = bin_of((lz - r) * (1.0f - DEPTH_EPS), zb.z, zb.w);
    const uint b1 = bin_of((lz + r) * (1.0f + DEPTH_EPS), zb.z, zb.w);
    const uint lmask = (b1 >= 31u ? 0xffffffffu : ((2u << b1) - 1u)) & ~((1u << b0) - 1u);
    if ((lmask & masks[t]) == 0u) return false;
  }
#endif
#endif
  /* Side planes of the tile's frustum from the projection's rows:
   * x_ndc >= xl  <=>  dot(row0 - xl * row3, v) >= 0  (w > 0). */
  const float4 row0 = mat_row(cam->proj, 0), row1 = mat_row(cam->proj, 1), row3 = mat_row(cam->proj, 3);
  const float xl = 2.0f * (float)(tx * TILE_SIZE) / (float)cam->width - 1.0f;
  const float xr = 2.0f * (float)min((uint)(tx + 1) * TILE_SIZE, cam->width) / (float)cam->width - 1.0f;
  const float yb = 2.0f * (float)(ty * TILE_SIZE) / (float)cam->height - 1.0f;
  const float yt = 2.0f * (float)min((uint)(ty + 1) * TILE_SIZE, cam->height) / (float)cam->height - 1.0f;
  if (!(sphere_inside_plane(row0 - xl * row3, lr->center) && sphere_inside_plane(xr * row3 - row0, lr->center) &&
        sphere_inside_plane(row1 - yb * row3, lr->center) && sphere_inside_plane(yt * row3 - row1, lr->center)))
    return false;
#if DEPTH_MODE != DEPTH_NONE
  return sphere_hits_tile_box(lr->center, xl, xr, yb, yt, bounds[t].x, bounds[t].y, cam);
#else
  return true;
#endif
}

/* Pass 1: each light's tile rectangle and the number of 32-bit words its
 * hit mask needs (one bit per tile of the rectangle). */
__kernel void light_rects(__global const PointLight* lights, uint n, CameraParams cam, uint tiles_x, uint tiles_y,
                          __global LightRect* rects, __global uint* mask_words) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const LightRect lr = light_rect(lights[i], &cam, tiles_x, tiles_y);
  rects[i] = lr;
  const int area = (lr.tx0 > lr.tx1 || lr.ty0 > lr.ty1) ? 0 : (lr.tx1 - lr.tx0 + 1) * (lr.ty1 - lr.ty0 + 1);
  mask_words[i] = (uint)(area + 31) / 32u;
}

/* Pass 2: the culling math, once per (light, tile of its rectangle): set the
 * tile's bit in the light's mask and count the light into the tile. */
__kernel void cull_mark(__global const LightRect* rects, uint n, CameraParams cam, uint tiles_x,
                        __global const float4* bounds, __global const uint* masks, __global const uint* mask_offsets,
                        __global uint* hit_masks, __global uint* counts) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const LightRect lr = rects[i];
  if (lr.tx0 > lr.tx1 || lr.ty0 > lr.ty1) return;
  __global uint* out = hit_masks + mask_offsets[i];
  uint word = 0, k = 0;
  for (int ty = lr.ty0; ty <= lr.ty1; ++ty)
    for (int tx = lr.tx0; tx <= lr.tx1; ++tx) {
      if (light_hits_tile(&lr, tx, ty, &cam, bounds, masks, tiles_x)) {
        word |= 1u << (k & 31u);
        atomic_inc(&counts[ty * tiles_x + tx]);
      }
      if ((++k & 31u) == 0u) {
        out[k / 32u - 1u] = word;
        word = 0;
      }
    }
  if (k & 31u) out[k / 32u] = word;
}

/* Pass 3: no math, each light scatters its index into the tiles of its mask. */
__kernel void cull_scatter(__global const LightRect* rects, uint n, uint tiles_x, __global const uint* mask_offsets,
                           __global const uint* hit_masks, __global const uint* offsets, __global uint* cursor,
                           __global uint* indices) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const LightRect lr = rects[i];
  if (lr.tx0 > lr.tx1 || lr.ty0 > lr.ty1) return;
  __global const uint* in = hit_masks + mask_offsets[i];
  const int w = lr.tx1 - lr.tx0 + 1;
  const uint area = (uint)(w * (lr.ty1 - lr.ty0 + 1));
  for (uint base = 0; base < area; base += 32u) {
    uint word = in[base / 32u];
    while (word) {
      const uint k = base + (31u - clz(word & (~word + 1u)));
      word &= word - 1u;
      const int row = (int)k / w;
      const uint t = (uint)(lr.ty0 + row) * tiles_x + (uint)(lr.tx0 + ((int)k - row * w));
      indices[offsets[t] + atomic_inc(&cursor[t])] = i;
    }
  }
}

/* Light grid for GLSL: (offset, count) per tile. */
__kernel void write_grid(__global const uint* offsets, __global const uint* counts, uint n_tiles,
                         __global LightRange* grid) {
  const uint t = get_global_id(0);
  if (t >= n_tiles) return;
  LightRange r;
  r.offset = offsets[t];
  r.count = counts[t];
  grid[t] = r;
}

/* ------------------------------------------------------------- GPU shape
 *
 * A work-item per bit of the hit masks: word w of the masks (32 tiles of one
 * light's rectangle, in the order cull_mark walks them) belongs to the light
 * whose mask_offsets range holds it. Same bits, same counts as the CPU shape;
 * only the order of the atomics differs. */

/* Most work-items per group of cull_mark_wg (the host asks for a power of two
 * >= 32 and <= this, fitted to the kernel's limits). */
#define MARK_WG 256

/* The light owning mask word w: the largest i with mask_offsets[i] <= w
 * (lights with empty rectangles share the next light's offset and own no word). */
inline uint light_of_word(__global const uint* mask_offsets, uint n, uint w) {
  uint lo = 0, hi = n;
  while (hi - lo > 1u) {
    const uint mid = (lo + hi) / 2u;
    if (mask_offsets[mid] <= w) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* Tile of bit k of light rectangle lr, or -1 when k is past its area. */
inline int tile_of_bit(const LightRect* lr, uint k, uint tiles_x, int* tx, int* ty) {
  const int w = lr->tx1 - lr->tx0 + 1;
  const uint area = (uint)(w * (lr->ty1 - lr->ty0 + 1));
  if (k >= area) return -1;
  const uint row = k / (uint)w; /* no `%`: see tile_minmax in reduce.cl */
  *tx = lr->tx0 + (int)(k - row * (uint)w);
  *ty = lr->ty0 + (int)row;
  return *ty * (int)tiles_x + *tx;
}

/* Pass 2, GPU shape: 32 work-items build one mask word through local memory. */
__kernel void cull_mark_wg(__global const LightRect* rects, uint n, uint words, CameraParams cam, uint tiles_x,
                           __global const float4* bounds, __global const uint* masks,
                           __global const uint* mask_offsets, __global uint* hit_masks, __global uint* counts) {
  __local uint lword[MARK_WG / 32];
  const size_t gid = get_global_id(0);
  const uint lid = get_local_id(0), lane = lid % 32u;
  const uint w = (uint)(gid / 32u);
  if (lane == 0u) lword[lid / 32u] = 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (w < words) {
    const uint i = light_of_word(mask_offsets, n, w);
    const LightRect lr = rects[i];
    int tx, ty;
    const int t = tile_of_bit(&lr, (w - mask_offsets[i]) * 32u + lane, tiles_x, &tx, &ty);
    if (t >= 0 && light_hits_tile(&lr, tx, ty, &cam, bounds, masks, tiles_x)) {
      atomic_or(&lword[lid / 32u], 1u << lane);
      atomic_inc(&counts[t]);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lane == 0u && w < words) hit_masks[w] = lword[lid / 32u];
}

/* Pass 3, GPU shape: a work-item per set bit scatters its light's index. */
__kernel void cull_scatter_wg(__global const LightRect* rects, uint n, uint words, uint tiles_x,
                              __global const uint* mask_offsets, __global const uint* hit_masks,
                              __global const uint* offsets, __global uint* cursor, __global uint* indices) {
  const size_t gid = get_global_id(0);
  const uint w = (uint)(gid / 32u), lane = (uint)(gid % 32u);
  if (w >= words || ((hit_masks[w] >> lane) & 1u) == 0u) return;
  const uint i = light_of_word(mask_offsets, n, w);
  const LightRect lr = rects[i];
  int tx, ty;
  const int t = tile_of_bit(&lr, (w - mask_offsets[i]) * 32u + lane, tiles_x, &tx, &ty);
  if (t >= 0) indices[offsets[t] + atomic_inc(&cursor[t])] = i;
}
