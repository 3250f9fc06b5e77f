/* Tiled shading (forward+ / tiled deferred) light culling.
 *
 *   tile_depth_bounds*   depth buffer -> per-tile [min, max] linear view depth,
 *                        a 32-bin 2.5D depth mask (Harada's) and the
 *                        view-space box of the tile's frustum between them
 *   tile_sides           side planes of each tile column and row
 *   light_rects          per light: screen tile rectangle, hit-mask size
 *   (scan of mask sizes -> per-light mask offsets)
 *   tile_blocks          CPU shape: the box around each 8 x 8 block of tiles
 *   cull_mark_chunked    CPU shape: a work-item per chunk of lights walks each
 *                        light's rectangle once (skipping the blocks it
 *                        cannot reach), sets the tile's bit in the light's
 *                        mask and counts into its own row of per-tile
 *                        counters (plain increments, no atomics)
 *   tile_chunk_totals    per tile: the sum of the chunk rows
 *   (scan of counts -> tile offsets and the list total)
 *   tile_chunk_bases     per tile: each chunk's first slot in the tile's list
 *   cull_scatter_chunked per chunk: indices[cursor[t]++] for its lights' bits
 *
 * Light-centric: the cost is the lights' covered tiles, not lights x tiles.
 * The per-pair work is small: whatever depends on the tile alone (side
 * planes, depth box) is computed once per tile, a row's side test once per
 * row and a column's once per column of the light's rectangle. Lists are
 * built by count -> scan -> fill and cannot overflow (the host sizes the
 * index list from the scan total); in the CPU shape each list is in
 * ascending light order.
 *
 * The GPU shape (cull_mark_wg, cull_scatter_wg) spreads the same (light,
 * tile) pairs over one work-item each, a light found from its hit-mask word,
 * so that a light covering the screen does not serialize one work-item while
 * the others idle, and counts with an atomic per list entry (order within a
 * list follows the atomics); tile_depth_bounds_wg gives each tile a
 * work-group. light_rects, tile_sides and write_grid are one work-item per
 * light, side or tile with coalesced reads and writes and serve both shapes.
 *
 * cull_mark / cull_scatter (CPU) and CULL_LEGACY=1 (GPU) are the culler before
 * the per-chunk counters and the hoisted math: per-pair math and an atomic
 * per list entry, kept for the benchmark's same-run comparison
 * (TileCullAlgorithm::PairAtomics). Same lists.
 *
 * Defines: TILE_SIZE (pixels), DEPTH_MODE (0 none, 1 min/max, 2 2.5D mask),
 * CULL_LEGACY (0 or 1). The view-space math shared with the clustered
 * kernels is in common/view_frustum.cl, write_grid in common/light_grid.cl.
 */
#include "gpu_types.h"

/* The C++ reference (host/tiled/TileGeometry.cpp) must reach bit-identical
 * decisions, so no fused multiply-adds that the host code would not make. */
#pragma OPENCL FP_CONTRACT OFF

#include "common/view_frustum.cl" /* mat_mul, mat_row, view_coord, frustum_xy_box, DEPTH_EPS */
#include "common/light_grid.cl"   /* write_grid */

#define DEPTH_NONE 0
#define DEPTH_MINMAX 1
#define DEPTH_MASK 2

/* ---------------------------------------------------------------- bounds */

/* NDC edges of tile column tx (left, right) or row ty (bottom, top). */
inline float2 tile_ndc_x(int tx, const CameraParams* cam) { return tile_ndc_span((uint)tx, TILE_SIZE, cam->width); }
inline float2 tile_ndc_y(int ty, const CameraParams* cam) { return tile_ndc_span((uint)ty, TILE_SIZE, cam->height); }

/* View-space x and y extent (x0, x1, y0, y1) of the tile's frustum between
 * the depths of its record zb (widened zmin, zmax): the box that
 * sphere_hits_tile_box tests, computed once per tile instead of per light. */
inline float4 tile_box(uint tx, uint ty, float4 zb, const CameraParams* cam) {
  return frustum_xy_box(tile_ndc_x((int)tx, cam), tile_ndc_y((int)ty, cam), zb.x, zb.y, cam->proj);
}

/* The tile depth range is widened by DEPTH_EPS (common/view_frustum.cl). */

/* Clamped as a float before the conversion: a light far outside the tile's
 * range gives a bin far outside int's range, and converting that is undefined. */
inline uint bin_of(float z, float zmin, float inv_range) {
  return (uint)fmin(fmax((z - zmin) * inv_range * 32.0f, 0.0f), 31.0f);
}

/* Tile record: (zmin, zmax) widened for the range test, then the exact zmin
 * and 1/(zmax - zmin) that the mask bins were computed with. Empty tile:
 * zmin > zmax. */
inline float4 widen(float zmin, float zmax) {
  if (zmin > zmax) return (float4)(INFINITY, -INFINITY, 0.0f, 0.0f);
  return (float4)(zmin - zmin * DEPTH_EPS, zmax + zmax * DEPTH_EPS, zmin, 1.0f / fmax(zmax - zmin, 1e-20f));
}

/* The tile records again as LANE_PLANES planes of n_tiles + LANE_PAD floats
 * (widened zmin, zmax, box x0, x1, y0, y1, then the mask's exact zmin, its
 * 1/(zmax - zmin) and the mask's bits as a float's bits), so that the CPU
 * culler tests 8 tiles of a row with one float8 load per plane; the pad keeps
 * a load at the last tile inside the buffer (lanes past a row's end are
 * masked off). */
#define LANE_PAD 8
#define LANE_PLANES 9
inline void write_lanes(__global float* lanes, uint t, uint n_tiles, float4 zb, float4 box, uint mask) {
  const size_t s = (size_t)n_tiles + LANE_PAD;
  const float v[LANE_PLANES] = {zb.x, zb.y, box.x, box.y, box.z, box.w, zb.z, zb.w, as_float(mask)};
  for (uint plane = 0; plane < LANE_PLANES; ++plane) lanes[plane * s + t] = v[plane];
  /* The last tile's item also fills the pad, as an empty tile (rejected by
   * every test): the loads past a row's end then read written values, so the
   * result does not depend on memory no kernel wrote (Oclgrind checks it). */
  if (t + 1u == n_tiles)
    for (uint p = n_tiles; p < n_tiles + LANE_PAD; ++p)
      for (uint plane = 0; plane < LANE_PLANES; ++plane)
        lanes[plane * s + p] = plane == 0u ? INFINITY : (plane < 6u ? -INFINITY : 0.0f);
}

/* CPU shape: one work-item per tile walks its pixels. */
__kernel void tile_depth_bounds(__global const float* depth, CameraParams cam, uint tiles_x, uint tiles_y,
                                __global float4* bounds, __global uint* masks, __global float4* boxes,
                                __global float* lanes) {
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
  const float4 zb = widen(zmin, zmax);
  bounds[t] = zb;
  masks[t] = mask;
  boxes[t] = tile_box(tx, ty, zb, &cam);
  write_lanes(lanes, t, tiles_x * tiles_y, zb, boxes[t], mask);
}

/* GPU shape: one work-group (TILE_SIZE x TILE_SIZE work-items, or fewer
 * that stride) per tile, local atomics on the float bits (positive floats
 * order like their uint bits). */
__kernel void tile_depth_bounds_wg(__global const float* depth, CameraParams cam, uint tiles_x, uint tiles_y,
                                   __global float4* bounds, __global uint* masks, __global float4* boxes,
                                   __global float* lanes) {
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
    const float4 zb = widen(zmin, zmax);
    bounds[t] = zb;
    masks[t] = lmask;
    boxes[t] = tile_box(tx, ty, zb, &cam);
    write_lanes(lanes, t, tiles_x * tiles_y, zb, boxes[t], lmask);
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
  /* The cube around the sphere, cut at the near plane where it straddles it:
   * every shaded point lies at or beyond the near plane, and the cut box is
   * all in front of the eye, so its corners' images bound what the light
   * can reach on screen. (Whole-screen rectangles for such lights cost a
   * pass over every tile each: thousands of them at a million lights.) */
  const float z_far = c.z - r, z_near = fmin(c.z + r, -cam->near_plane);
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  for (int i = 0; i < 8; ++i) {
    const float4 corner = (float4)(c.x + ((i & 1) ? r : -r), c.y + ((i & 2) ? r : -r), (i & 4) ? z_near : z_far, 1.0f);
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

/* Sphere against the view-space AABB of the tile's frustum between its
 * depth bounds: removes the false positives of plane tests near corners. */
inline bool sphere_hits_tile_box(float4 c, float xl, float xr, float yb, float yt, float zmin, float zmax,
                                 const CameraParams* cam) {
  const float4 box = frustum_xy_box((float2)(xl, xr), (float2)(yb, yt), zmin, zmax, cam->proj);
  const float dx = c.x - clamp(c.x, box.x, box.y), dy = c.y - clamp(c.y, box.z, box.w);
  const float dz = -c.z - clamp(-c.z, zmin, zmax);
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
  const float2 ex = tile_ndc_x(tx, cam), ey = tile_ndc_y(ty, cam);
  const float xl = ex.x, xr = ex.y, yb = ey.x, yt = ey.y;
  if (!(sphere_inside_plane(row0 - xl * row3, lr->center) && sphere_inside_plane(xr * row3 - row0, lr->center) &&
        sphere_inside_plane(row1 - yb * row3, lr->center) && sphere_inside_plane(yt * row3 - row1, lr->center)))
    return false;
#if DEPTH_MODE != DEPTH_NONE
  return sphere_hits_tile_box(lr->center, xl, xr, yb, yt, bounds[t].x, bounds[t].y, cam);
#else
  return true;
#endif
}

/* ------------------------------------------------ hoisted culling math
 *
 * The same decisions as light_hits_tile, with everything that depends on the
 * tile alone computed once per tile (tile_sides, tile_box in the bounds
 * kernels) instead of once per (light, tile): the side planes of a tile
 * column or row and their lengths, and the view-space box of the tile's
 * frustum. The tests are the same float operations on the same values, and a
 * conjunction does not depend on the order of its terms, so the lists are
 * bit-identical to the per-pair math (the C++ twin is lightHitsTile).
 */

/* One side pair of a tile column (left, right) or row (bottom, top): the
 * planes and the lengths of their normals. 48 bytes (kTileSideBytes). */
typedef struct {
  float4 lo, hi;
  float lo_len, hi_len, pad0, pad1;
} TileSide;

/* sides[0, tiles_x): columns; sides[tiles_x, tiles_x + tiles_y): rows. */
__kernel void tile_sides(CameraParams cam, uint tiles_x, uint tiles_y, __global TileSide* sides) {
  const uint i = get_global_id(0);
  if (i >= tiles_x + tiles_y) return;
  const float4 row3 = mat_row(cam.proj, 3);
  const bool col = i < tiles_x;
  const float4 rowk = mat_row(cam.proj, col ? 0 : 1);
  const float2 e = col ? tile_ndc_x((int)i, &cam) : tile_ndc_y((int)(i - tiles_x), &cam);
  TileSide s;
  s.lo = rowk - e.x * row3;
  s.hi = e.y * row3 - rowk;
  s.lo_len = sqrt(s.lo.x * s.lo.x + s.lo.y * s.lo.y + s.lo.z * s.lo.z);
  s.hi_len = sqrt(s.hi.x * s.hi.x + s.hi.y * s.hi.y + s.hi.z * s.hi.z);
  s.pad0 = s.pad1 = 0.0f;
  sides[i] = s;
}

/* Blocks of BLOCK_TILES x BLOCK_TILES tiles: the box around their tiles'
 * boxes (lo: the least widened zmin, box x0, y0; hi: the greatest widened
 * zmax, x1, y1, over the block's non-empty tiles; empty block: lo.x > hi.x).
 * A light that misses a block's box misses every tile in it by the same
 * comparisons on the same floats (each tile's box lies inside it, and a
 * float difference to a farther bound is never smaller), so mark_light skips
 * the block's tiles without changing a decision: at 8 px tiles most of a
 * large light's rectangle is behind nearer geometry or in its corners. */
#define BLOCK_TILES 8
__kernel void tile_blocks(__global const float4* bounds, __global const float4* boxes, uint tiles_x, uint tiles_y,
                          uint blocks_x, __global float4* blocks_lo, __global float4* blocks_hi) {
  const uint b = get_global_id(0);
  const uint blocks_y = (tiles_y + BLOCK_TILES - 1u) / BLOCK_TILES;
  if (b >= blocks_x * blocks_y) return;
  const uint by = b / blocks_x, bx = b - by * blocks_x;
  const uint x0 = bx * BLOCK_TILES, y0 = by * BLOCK_TILES;
  const uint x1 = min(x0 + BLOCK_TILES, tiles_x), y1 = min(y0 + BLOCK_TILES, tiles_y);
  float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
  for (uint y = y0; y < y1; ++y)
    for (uint x = x0; x < x1; ++x) {
      const uint t = y * tiles_x + x;
      const float4 zb = bounds[t], box = boxes[t];
      if (zb.x > zb.y) continue; /* empty tile */
      lo = fmin(lo, (float4)(zb.x, box.x, box.z, 0.0f));
      hi = fmax(hi, (float4)(zb.y, box.y, box.w, 0.0f));
    }
  blocks_lo[b] = lo;
  blocks_hi[b] = hi;
}

/* The range and box terms of the depth test: does the sphere c reach the
 * view-space box (x0, x1, y0, y1) = box between the widened depths zlo and
 * zhi (empty: zlo > zhi)? Tiles (depth_and_box_ok) and blocks of tiles
 * (blocks_in_reach) ask it with the same operations. */
inline bool reaches_depth_box(float4 c, float zlo, float zhi, float4 box) {
  const float lz = -c.z, r = c.w;
  if (zlo > zhi || lz + r < zlo || lz - r > zhi) return false;
  const float dx = c.x - clamp(c.x, box.x, box.y), dy = c.y - clamp(c.y, box.z, box.w), dz = lz - clamp(lz, zlo, zhi);
  return dx * dx + dy * dy + dz * dz <= c.w * c.w * (1.0f + 4.0f * DEPTH_EPS);
}

/* Bit i: block column bx0 + i of block row `by` may hold a tile that the
 * light reaches: depth_and_box_ok's range and box terms on the block's box
 * (i < 64; the caller treats the rest as kept). */
inline ulong blocks_in_reach(float4 c, uint by, uint bx0, uint bx1, uint blocks_x, __global const float4* blocks_lo,
                             __global const float4* blocks_hi) {
  ulong keep = 0;
  for (uint i = 0; i < 64u && bx0 + i <= bx1; ++i) {
    const float4 lo = blocks_lo[by * blocks_x + bx0 + i], hi = blocks_hi[by * blocks_x + bx0 + i];
    if (reaches_depth_box(c, lo.x, hi.x, (float4)(lo.y, hi.y, lo.z, hi.z))) keep |= (ulong)1 << i;
  }
  return keep;
}

/* The 8 tiles x .. x + 7 of a row as bits, kept where their block is. */
inline uint block_bits8(ulong keep, uint x, uint bx0) {
  const uint rel = x / BLOCK_TILES - bx0, split = BLOCK_TILES - x % BLOCK_TILES;
  const uint first = (1u << split) - 1u;
  const uint a = rel < 64u ? (uint)(keep >> rel) & 1u : 1u, b = rel + 1u < 64u ? (uint)(keep >> (rel + 1u)) & 1u : 1u;
  return ((a ? first : 0u) | (b ? ~first : 0u)) & 0xffu;
}

/* sphere_inside_plane with the normal's length given. */
inline bool inside_plane_len(float4 p, float len, float4 c) {
  return p.x * c.x + p.y * c.y + p.z * c.z + p.w > -c.w * len;
}
inline bool inside_side(__global const TileSide* side, float4 c) {
  const TileSide s = *side;
  return inside_plane_len(s.lo, s.lo_len, c) && inside_plane_len(s.hi, s.hi_len, c);
}

/* The depth terms of light_hits_tile (range, 2.5D mask) and its box test on
 * the precomputed box; true without depth bounds. */
inline bool depth_and_box_ok(float4 c, uint t, __global const float4* bounds, __global const uint* masks,
                             __global const float4* boxes) {
#if DEPTH_MODE != DEPTH_NONE
  const float4 zb = bounds[t];
  if (!reaches_depth_box(c, zb.x, zb.y, boxes[t])) return false;
#if DEPTH_MODE == DEPTH_MASK
  const float lz = -c.z, r = c.w;
  const uint b0 = bin_of((lz - r) * (1.0f - DEPTH_EPS), zb.z, zb.w);
  const uint b1 = bin_of((lz + r) * (1.0f + DEPTH_EPS), zb.z, zb.w);
  const uint lmask = (b1 >= 31u ? 0xffffffffu : ((2u << b1) - 1u)) & ~((1u << b0) - 1u);
  if ((lmask & masks[t]) == 0u) return false;
#endif
  return true;
#else
  return true;
#endif
}

inline bool light_hits_tile_fast(float4 c, int tx, int ty, uint tiles_x, __global const float4* bounds,
                                 __global const uint* masks, __global const float4* boxes,
                                 __global const TileSide* sides) {
  const uint t = (uint)ty * tiles_x + (uint)tx;
  return depth_and_box_ok(c, t, bounds, masks, boxes) && inside_side(sides + tx, c) &&
         inside_side(sides + tiles_x + ty, c);
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

/* ------------------------------------------------------------- CPU shape
 *
 * Per-chunk counting instead of an atomic per list entry (PoCL serializes
 * those): work-item c owns the lights [c * per, (c + 1) * per) and row c of
 * chunk_counts (a counter per tile), so cull_mark_chunked counts with plain
 * increments; tile_chunk_totals sums the rows per tile for the scan;
 * tile_chunk_bases turns each row into that chunk's write cursors (the tile's
 * offset plus the counts of the chunks before it); cull_scatter_chunked
 * writes with them. Every chunk holds at least one light (the host sizes
 * `per` so), every row is written before it is read, and each tile's list
 * comes out in ascending light order (chunks in order, lights in order).
 */

/* Columns of a light's rectangle whose side test mark_light caches (8 x 32);
 * wider rectangles test the rest per tile. */
#define COL_WORDS 8

/* The 2.5D mask term of depth_and_box_ok for 8 tiles, lane by lane: the
 * same bins from the same float operations (convert_uint8 truncates as the
 * scalar cast does; a shift of 2u by 31 gives 0, so 0 - 1 is the full mask
 * that the scalar code selects). */
inline int8 mask_hits8(float4 c, uint t0, size_t s, __global const float* lanes) {
  const float8 zmin = vload8(0, lanes + 6 * s + t0), inv = vload8(0, lanes + 7 * s + t0);
  const uint8 bits = as_uint8(vload8(0, lanes + 8 * s + t0));
  const float lz = -c.z, r = c.w;
  const float8 lo = (float8)((lz - r) * (1.0f - DEPTH_EPS)), hi = (float8)((lz + r) * (1.0f + DEPTH_EPS));
  const uint8 b0 = convert_uint8(fmin(fmax((lo - zmin) * inv * 32.0f, 0.0f), 31.0f));
  const uint8 b1 = convert_uint8(fmin(fmax((hi - zmin) * inv * 32.0f, 0.0f), 31.0f));
  const uint8 lmask = (((uint8)(2u) << b1) - 1u) & ~(((uint8)(1u) << b0) - 1u);
  return (lmask & bits) != 0u;
}

/* depth_and_box_ok for the 8 tiles t0 .. t0 + 7 of a row, as bits 0..7: the
 * same comparisons lane by lane. A comparison is -1 where true, and a NaN
 * fails it as in the scalar code; ~ turns "reject" into "keep" without
 * changing that. */
inline uint depth_and_box_bits8(float4 c, uint t0, size_t s, __global const float* lanes) {
  const float8 zlo = vload8(0, lanes + t0), zhi = vload8(0, lanes + s + t0);
  const float8 x0 = vload8(0, lanes + 2 * s + t0), x1 = vload8(0, lanes + 3 * s + t0);
  const float8 y0 = vload8(0, lanes + 4 * s + t0), y1 = vload8(0, lanes + 5 * s + t0);
  const float lz = -c.z, r = c.w;
  const float8 cx = (float8)(c.x), cy = (float8)(c.y), cz = (float8)(-c.z);
  const float8 dx = cx - clamp(cx, x0, x1), dy = cy - clamp(cy, y0, y1), dz = cz - clamp(cz, zlo, zhi);
  int8 ok = ~(zlo > zhi) & ~((float8)(lz + r) < zlo) & ~((float8)(lz - r) > zhi) &
           (dx * dx + dy * dy + dz * dz <= (float8)(c.w * c.w * (1.0f + 4.0f * DEPTH_EPS)));
#if DEPTH_MODE == DEPTH_MASK
  ok &= mask_hits8(c, t0, s, lanes);
#endif
  return (uint)((ok.s0 & 1) | (ok.s1 & 2) | (ok.s2 & 4) | (ok.s3 & 8) | (ok.s4 & 16) | (ok.s5 & 32) |
                (ok.s6 & 64) | (ok.s7 & 128));
}

/* Bit b of cols[j / 32]: the light is inside column j + b's side planes
 * (j + b < wc). */
inline void column_bits(__global const TileSide* col_sides, uint wc, float4 c, uint* cols) {
  for (uint j = 0; j < wc; j += 32u) {
    uint bits = 0;
    for (uint b = 0; b < min(32u, wc - j); ++b)
      if (inside_side(col_sides + j + b, c)) bits |= 1u << b;
    cols[j / 32u] = bits;
  }
}

/* Hit mask of one light (a bit per tile of its rectangle, row-major) and its
 * counts. The side tests are separable: a row's once per row (a row that the
 * sphere misses is skipped whole), a column's once per column; the depth and
 * box terms 8 tiles at a time. */
inline void mark_light(const LightRect* lr, uint tiles_x, uint n_tiles, __global const float* lanes,
                       __global const TileSide* sides, __global const float4* blocks_lo,
                       __global const float4* blocks_hi, uint blocks_x,
                       __global uint* out, __global uint* counts) {
  const uint w = (uint)(lr->tx1 - lr->tx0 + 1), area = w * (uint)(lr->ty1 - lr->ty0 + 1);
  for (uint k = 0; k < (area + 31u) / 32u; ++k) out[k] = 0u;
  const float4 c = lr->center;
  __global const TileSide* col_sides = sides + lr->tx0;
  uint cols[COL_WORDS];
  const uint wc = min(w, 32u * COL_WORDS);
  bool have_cols = false; /* tested at the first row that needs them: most rectangles have none */
  const size_t s = (size_t)n_tiles + LANE_PAD;
  const uint bx0 = (uint)lr->tx0 / BLOCK_TILES, bx1 = (uint)lr->tx1 / BLOCK_TILES;
  uint block_row = UINT_MAX;
  ulong keep = ~(ulong)0;
  uint k = 0; /* bit of the row's first tile */
  for (int ty = lr->ty0; ty <= lr->ty1; ++ty, k += w) {
#if DEPTH_MODE != DEPTH_NONE
    if ((uint)ty / BLOCK_TILES != block_row) {
      block_row = (uint)ty / BLOCK_TILES;
      keep = blocks_in_reach(c, block_row, bx0, bx1, blocks_x, blocks_lo, blocks_hi);
    }
    if (keep == 0u && bx1 - bx0 < 64u) continue; /* the whole row is behind or before the light */
#endif
    if (!inside_side(sides + tiles_x + ty, c)) continue;
    if (!have_cols) column_bits(col_sides, wc, c, cols);
    have_cols = true;
    const uint row = (uint)ty * tiles_x + (uint)lr->tx0;
    for (uint j = 0; j < w; j += 8u) {
#if DEPTH_MODE != DEPTH_NONE
      const uint reach = block_bits8(keep, (uint)lr->tx0 + j, bx0);
      if (reach == 0u) continue;
#else
      const uint reach = 0xffu;
#endif
      uint col = (j + 8u <= wc) ? (cols[j / 32u] >> (j & 31u)) & reach : 0u;
      for (uint l = 0; j + 8u > wc && l < 8u && j + l < w; ++l)
        if (j + l < wc ? ((cols[(j + l) / 32u] >> ((j + l) & 31u)) & 1u) : inside_side(col_sides + j + l, c))
          col |= 1u << l;
      if (w - j < 8u) col &= (1u << (w - j)) - 1u;
      col &= reach;
#if DEPTH_MODE != DEPTH_NONE
      if (col) col &= depth_and_box_bits8(c, row + j, s, lanes);
#endif
      while (col) {
        const uint l = 31u - clz(col & (~col + 1u));
        col &= col - 1u;
        out[(k + j + l) / 32u] |= 1u << ((k + j + l) & 31u);
        ++counts[row + j + l];
      }
    }
  }
}

__kernel void cull_mark_chunked(__global const LightRect* rects, uint n, uint per, uint n_tiles, uint tiles_x,
                                __global const float* lanes, __global const TileSide* sides,
                                __global const float4* blocks_lo, __global const float4* blocks_hi, uint blocks_x,
                                __global const uint* mask_offsets,
                                __global uint* hit_masks, __global uint* chunk_counts) {
  const size_t c = get_global_id(0);
  const ulong i0 = (ulong)c * per;
  if (i0 >= n) return;
  const uint i1 = (uint)min((ulong)n, i0 + per);
  __global uint* counts = chunk_counts + c * n_tiles;
  for (uint t = 0; t < n_tiles; ++t) counts[t] = 0u;
  for (uint i = (uint)i0; i < i1; ++i) {
    const LightRect lr = rects[i];
    if (lr.tx0 <= lr.tx1 && lr.ty0 <= lr.ty1)
      mark_light(&lr, tiles_x, n_tiles, lanes, sides, blocks_lo, blocks_hi, blocks_x, hit_masks + mask_offsets[i],
                 counts);
  }
}

/* A tile's list length: the sum of its chunk counters (each <= per, the sum <= n). */
__kernel void tile_chunk_totals(__global const uint* chunk_counts, uint chunks, uint n_tiles, __global uint* counts) {
  const uint t = get_global_id(0);
  if (t >= n_tiles) return;
  uint s = 0;
  for (uint c = 0; c < chunks; ++c) s += chunk_counts[(size_t)c * n_tiles + t];
  counts[t] = s;
}

/* In place: chunk c's counter of tile t becomes its first slot in the tile's list. */
__kernel void tile_chunk_bases(__global uint* chunk_counts, uint chunks, uint n_tiles, __global const uint* offsets) {
  const uint t = get_global_id(0);
  if (t >= n_tiles) return;
  uint run = offsets[t];
  for (uint c = 0; c < chunks; ++c) {
    const size_t at = (size_t)c * n_tiles + t;
    const uint v = chunk_counts[at];
    chunk_counts[at] = run;
    run += v;
  }
}

__kernel void cull_scatter_chunked(__global const LightRect* rects, uint n, uint per, uint n_tiles, uint tiles_x,
                                   __global const uint* mask_offsets, __global const uint* hit_masks,
                                   __global uint* chunk_bases, __global uint* indices) {
  const size_t c = get_global_id(0);
  const ulong i0 = (ulong)c * per;
  if (i0 >= n) return;
  const uint i1 = (uint)min((ulong)n, i0 + per);
  __global uint* cursor = chunk_bases + c * n_tiles;
  for (uint i = (uint)i0; i < i1; ++i) {
    const LightRect lr = rects[i];
    if (lr.tx0 > lr.tx1 || lr.ty0 > lr.ty1) continue;
    __global const uint* in = hit_masks + mask_offsets[i];
    const uint w = (uint)(lr.tx1 - lr.tx0 + 1), area = w * (uint)(lr.ty1 - lr.ty0 + 1);
    for (uint base = 0; base < area; base += 32u) {
      uint word = in[base / 32u];
      while (word) {
        const uint k = base + (31u - clz(word & (~word + 1u)));
        word &= word - 1u;
        const uint t = (uint)(lr.ty0 + (int)(k / w)) * tiles_x + (uint)lr.tx0 + k % w;
        indices[cursor[t]++] = i;
      }
    }
  }
}

/* The light grid for GLSL: write_grid (common/light_grid.cl). */

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
                           __global const float4* boxes, __global const TileSide* sides,
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
#if CULL_LEGACY
    const bool hit = t >= 0 && light_hits_tile(&lr, tx, ty, &cam, bounds, masks, tiles_x);
#else
    const bool hit = t >= 0 && light_hits_tile_fast(lr.center, tx, ty, tiles_x, bounds, masks, boxes, sides);
#endif
    if (hit) {
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
