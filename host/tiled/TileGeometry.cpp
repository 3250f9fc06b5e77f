#include "host/tiled/TileGeometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/util/Error.hpp"

namespace ml {
namespace {

struct V4 {
  float x, y, z, w;
};
V4 mul(const float* m, V4 v) {
  return {m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12] * v.w, m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13] * v.w,
          m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14] * v.w, m[3] * v.x + m[7] * v.y + m[11] * v.z + m[15] * v.w};
}
V4 row(const float* m, int r) { return {m[r], m[4 + r], m[8 + r], m[12 + r]}; }
V4 sub(V4 a, V4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
V4 scale(V4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
bool insidePlane(V4 p, const LightTileRect& c) {
  return p.x * c.cx + p.y * c.cy + p.z * c.cz + p.w > -c.r * std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}
float viewCoord(float n, float d, float p_diag, float p_off) { return d * (n + p_off) / p_diag; }

bool sphereHitsTileBox(const LightTileRect& c, float xl, float xr, float yb, float yt, float zmin, float zmax,
                       const gpu::CameraParams& cam) {
  const float p00 = cam.proj[0], p20 = cam.proj[8], p11 = cam.proj[5], p21 = cam.proj[9];
  const float x0 = std::fmin(std::fmin(viewCoord(xl, zmin, p00, p20), viewCoord(xl, zmax, p00, p20)),
                             std::fmin(viewCoord(xr, zmin, p00, p20), viewCoord(xr, zmax, p00, p20)));
  const float x1 = std::fmax(std::fmax(viewCoord(xl, zmin, p00, p20), viewCoord(xl, zmax, p00, p20)),
                             std::fmax(viewCoord(xr, zmin, p00, p20), viewCoord(xr, zmax, p00, p20)));
  const float y0 = std::fmin(std::fmin(viewCoord(yb, zmin, p11, p21), viewCoord(yb, zmax, p11, p21)),
                             std::fmin(viewCoord(yt, zmin, p11, p21), viewCoord(yt, zmax, p11, p21)));
  const float y1 = std::fmax(std::fmax(viewCoord(yb, zmin, p11, p21), viewCoord(yb, zmax, p11, p21)),
                             std::fmax(viewCoord(yt, zmin, p11, p21), viewCoord(yt, zmax, p11, p21)));
  const float dx = c.cx - std::clamp(c.cx, x0, x1), dy = c.cy - std::clamp(c.cy, y0, y1);
  const float dz = -c.cz - std::clamp(-c.cz, zmin, zmax);
  return dx * dx + dy * dy + dz * dz <= c.r * c.r * (1.0f + 4.0f * kTileDepthEps);
}

// Clamped as a float before the conversion, as the kernel's bin_of: a light
// far outside the tile's range gives a bin beyond int's range (undefined to
// convert; clang's UBSan reported -3.2e25), and NaN becomes bin 0.
unsigned binOf(float z, float zmin, float inv) {
  return static_cast<unsigned>(std::fmin(std::fmax((z - zmin) * inv * 32.0f, 0.0f), 31.0f));
}

}  // namespace

TileDepthMode parseTileDepthMode(const std::string& s) {
  if (s == "none") return TileDepthMode::None;
  if (s == "minmax") return TileDepthMode::MinMax;
  if (s == "mask") return TileDepthMode::Mask;
  throw UserError("--tile-depth: expected none, minmax or mask, got '" + s + "'");
}

const char* tileDepthModeName(TileDepthMode m) {
  switch (m) {
    case TileDepthMode::None: return "none";
    case TileDepthMode::MinMax: return "minmax";
    case TileDepthMode::Mask: return "mask";
  }
  return "?";
}

TileDepth tileDepth(const float* depth, const gpu::CameraParams& cam, const TileGrid& g, unsigned tx, unsigned ty,
                    TileDepthMode mode) {
  const unsigned x0 = tx * g.tile_size, y0 = ty * g.tile_size;
  const unsigned x1 = std::min(x0 + g.tile_size, g.width), y1 = std::min(y0 + g.tile_size, g.height);
  float zmin = std::numeric_limits<float>::infinity(), zmax = -zmin;
  for (unsigned y = y0; y < y1; ++y)
    for (unsigned x = x0; x < x1; ++x) {
      const float d = depth[y * g.width + x];
      if (gpu::is_sky_depth(d)) continue;
      const float z = gpu::linear_depth(d, cam);
      zmin = std::fmin(zmin, z);
      zmax = std::fmax(zmax, z);
    }
  TileDepth td{};
  if (zmin > zmax) {
    td.zmin_widened = std::numeric_limits<float>::infinity();
    td.zmax_widened = -td.zmin_widened;
    return td;
  }
  td.zmin = zmin;
  td.inv_range = 1.0f / std::fmax(zmax - zmin, 1e-20f);
  td.zmin_widened = zmin - zmin * kTileDepthEps;
  td.zmax_widened = zmax + zmax * kTileDepthEps;
  if (mode == TileDepthMode::Mask)
    for (unsigned y = y0; y < y1; ++y)
      for (unsigned x = x0; x < x1; ++x) {
        const float d = depth[y * g.width + x];
        if (!gpu::is_sky_depth(d)) td.mask |= 1u << binOf(gpu::linear_depth(d, cam), td.zmin, td.inv_range);
      }
  return td;
}

LightTileRect lightTileRect(const gpu::PointLight& l, const gpu::CameraParams& cam, const TileGrid& g) {
  LightTileRect lr{};
  const float r = l.position_radius.w;
  const V4 c = mul(cam.view, {l.position_radius.x, l.position_radius.y, l.position_radius.z, 1.0f});
  lr.cx = c.x;
  lr.cy = c.y;
  lr.cz = c.z;
  lr.r = r;
  lr.tx0 = 0;
  lr.ty0 = 0;
  lr.tx1 = static_cast<int>(g.tilesX()) - 1;
  lr.ty1 = static_cast<int>(g.tilesY()) - 1;
  if (c.z - r > -cam.near_plane || -c.z - r > cam.far_plane) {
    lr.tx0 = 1;
    lr.tx1 = 0;
    return lr;
  }
  // The cube cut at the near plane where the sphere straddles it (light_rect).
  const float z_far = c.z - r, z_near = std::fmin(c.z + r, -cam.near_plane);
  float lox = INFINITY, loy = INFINITY, hix = -INFINITY, hiy = -INFINITY;
  for (int i = 0; i < 8; ++i) {
    const V4 corner{c.x + ((i & 1) ? r : -r), c.y + ((i & 2) ? r : -r), (i & 4) ? z_near : z_far, 1.0f};
    const V4 clip = mul(cam.proj, corner);
    const float nx = clip.x / clip.w, ny = clip.y / clip.w;
    lox = std::fmin(lox, nx);
    loy = std::fmin(loy, ny);
    hix = std::fmax(hix, nx);
    hiy = std::fmax(hiy, ny);
  }
  if (hix < -1.0f || hiy < -1.0f || lox > 1.0f || loy > 1.0f) {
    lr.tx0 = 1;
    lr.tx1 = 0;
    return lr;
  }
  const float ts = static_cast<float>(g.tile_size);
  auto tile = [&](float ndc, float size, int last) {
    const float p = (std::clamp(ndc, -1.0f, 1.0f) * 0.5f + 0.5f) * size;
    return std::clamp(static_cast<int>(std::floor(p / ts)), 0, last);
  };
  const int lx = static_cast<int>(g.tilesX()) - 1, ly = static_cast<int>(g.tilesY()) - 1;
  lr.tx0 = tile(lox, float(g.width), lx);
  lr.ty0 = tile(loy, float(g.height), ly);
  lr.tx1 = tile(hix, float(g.width), lx);
  lr.ty1 = tile(hiy, float(g.height), ly);
  return lr;
}

bool lightHitsTile(const LightTileRect& lr, unsigned tx, unsigned ty, const gpu::CameraParams& cam,
                   const TileGrid& g, const TileDepth& td, TileDepthMode mode) {
  if (mode != TileDepthMode::None) {
    if (td.empty()) return false;
    const float lz = -lr.cz, r = lr.r;
    if (lz + r < td.zmin_widened || lz - r > td.zmax_widened) return false;
    if (mode == TileDepthMode::Mask) {
      const unsigned b0 = binOf((lz - r) * (1.0f - kTileDepthEps), td.zmin, td.inv_range);
      const unsigned b1 = binOf((lz + r) * (1.0f + kTileDepthEps), td.zmin, td.inv_range);
      const std::uint32_t lmask = (b1 >= 31u ? 0xffffffffu : ((2u << b1) - 1u)) & ~((1u << b0) - 1u);
      if ((lmask & td.mask) == 0u) return false;
    }
  }
  const V4 row0 = row(cam.proj, 0), row1 = row(cam.proj, 1), row3 = row(cam.proj, 3);
  const float ts = static_cast<float>(g.tile_size);
  const float xl = 2.0f * (tx * ts) / float(g.width) - 1.0f;
  const float xr = 2.0f * float(std::min((tx + 1) * g.tile_size, g.width)) / float(g.width) - 1.0f;
  const float yb = 2.0f * (ty * ts) / float(g.height) - 1.0f;
  const float yt = 2.0f * float(std::min((ty + 1) * g.tile_size, g.height)) / float(g.height) - 1.0f;
  if (!(insidePlane(sub(row0, scale(row3, xl)), lr) && insidePlane(sub(scale(row3, xr), row0), lr) &&
        insidePlane(sub(row1, scale(row3, yb)), lr) && insidePlane(sub(scale(row3, yt), row1), lr)))
    return false;
  if (mode == TileDepthMode::None) return true;
  return sphereHitsTileBox(lr, xl, xr, yb, yt, td.zmin_widened, td.zmax_widened, cam);
}

}  // namespace ml
