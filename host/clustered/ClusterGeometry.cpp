#include "host/clustered/ClusterGeometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "host/assign/LightFootprint.hpp"
#include "host/tiled/TileGeometry.hpp"
#include "host/util/Error.hpp"

// Must round like kernels/clustered/*.cl, which have FP_CONTRACT OFF: the
// default x86-64 target has no FMA, so GCC cannot contract here either.

namespace ml {

unsigned bitsFor(unsigned count) {
  unsigned b = 0;
  while (b < 32 && (1ull << b) < count) ++b;
  return b;
}

unsigned autoClusterTile(unsigned width, unsigned height, double light_pixels) {
  (void)width;
  return tileForLights(light_pixels, kClusterTilePerLightPixel, 8u, height >= 720 ? 32u : 16u);
}

ClusterGrid ClusterGrid::make(const gpu::CameraParams& cam, unsigned tile_size) {
  if (tile_size < 1 || tile_size > kMaxClusterTile)
    throw UserError("--cluster-tile: tile size must be 1.." + std::to_string(kMaxClusterTile) + ", got " +
                    std::to_string(tile_size));
  if (cam.width == 0 || cam.height == 0) throw UserError("clustered: empty viewport");
  if (!(cam.near_plane > 0.0f) || !(cam.far_plane > cam.near_plane))
    throw UserError("clustered: needs 0 < near < far");
  ClusterGrid g;
  g.tile_size = tile_size;
  g.width = cam.width;
  g.height = cam.height;
  g.tiles_x = (cam.width + tile_size - 1) / tile_size;
  g.tiles_y = (cam.height + tile_size - 1) / tile_size;
  const double q = 1.0 + 2.0 * double(cam.tan_half_fovy) / double(g.tiles_y);
  const double span = std::log(double(cam.far_plane) / double(cam.near_plane)) / std::log(q);
  g.slices = std::max(1u, unsigned(std::ceil(span - 1e-9)));
  g.x_bits = bitsFor(g.tiles_x);
  g.y_bits = bitsFor(g.tiles_y);
  g.k_bits = bitsFor(g.slices);
  if (g.keyBits() > 31)
    throw UserError("clustered: cluster key needs " + std::to_string(g.keyBits()) +
                    " bits (max 31); use a larger --cluster-tile or a smaller far/near ratio");
  g.slice_bounds.resize(g.slices + 1);
  for (unsigned k = 0; k <= g.slices; ++k) g.slice_bounds[k] = float(double(cam.near_plane) * std::pow(q, double(k)));
  g.slice_bounds[0] = cam.near_plane;
  g.slice_bounds[g.slices] = std::max(g.slice_bounds[g.slices], cam.far_plane);
  return g;
}

std::vector<std::uint32_t> ClusterGrid::tileOffsets() const {
  std::vector<std::uint32_t> off(std::size_t(tiles_x) * tiles_y + 1, 0);
  for (unsigned ty = 0; ty < tiles_y; ++ty)
    for (unsigned tx = 0; tx < tiles_x; ++tx) {
      const unsigned w = std::min(tile_size, width - tx * tile_size), h = std::min(tile_size, height - ty * tile_size);
      const std::size_t t = std::size_t(ty) * tiles_x + tx;
      off[t + 1] = off[t] + w * h;
    }
  return off;
}

unsigned sliceOfDepth(float z, const ClusterGrid& g) {
  unsigned lo = 0, hi = g.slices;
  while (hi - lo > 1) {
    const unsigned mid = (lo + hi) / 2;
    if (g.slice_bounds[mid] <= z) lo = mid;
    else hi = mid;
  }
  return lo;
}

std::vector<std::uint32_t> referenceKeys(const float* depth, const gpu::CameraParams& cam, const ClusterGrid& g) {
  std::vector<std::uint32_t> keys(std::size_t(cam.width) * cam.height);
  for (unsigned y = 0; y < cam.height; ++y)
    for (unsigned x = 0; x < cam.width; ++x) {
      const std::size_t p = std::size_t(y) * cam.width + x;
      const float d = depth[p];
      keys[p] = gpu::is_sky_depth(d)
                    ? kClusterInvalid
                    : g.key(x / g.tile_size, y / g.tile_size, sliceOfDepth(gpu::linear_depth(d, cam), g));
    }
  return keys;
}

namespace {
float viewCoord(float n, float d, float p_diag, float p_off) { return d * (n + p_off) / p_diag; }
}  // namespace

ClusterBox clusterBox(std::uint32_t key, const gpu::CameraParams& cam, const ClusterGrid& g) {
  const unsigned i = g.tileX(key), j = g.tileY(key), k = g.sliceOf(key);
  const unsigned T = g.tile_size;
  const float xl = 2.0f * float(i * T) / float(cam.width) - 1.0f;
  const float xr = 2.0f * float(std::min((i + 1) * T, cam.width)) / float(cam.width) - 1.0f;
  const float yb = 2.0f * float(j * T) / float(cam.height) - 1.0f;
  const float yt = 2.0f * float(std::min((j + 1) * T, cam.height)) / float(cam.height) - 1.0f;
  // Slice 0 also holds the (rare) pixels in front of near after rounding.
  const float zmin = k == 0 ? 0.0f : g.slice_bounds[k] - g.slice_bounds[k] * kClusterDepthEps;
  const float zmax = g.slice_bounds[k + 1] + g.slice_bounds[k + 1] * kClusterDepthEps;
  const float p00 = cam.proj[0], p20 = cam.proj[8], p11 = cam.proj[5], p21 = cam.proj[9];
  ClusterBox b;
  b.x0 = std::fmin(std::fmin(viewCoord(xl, zmin, p00, p20), viewCoord(xl, zmax, p00, p20)),
                   std::fmin(viewCoord(xr, zmin, p00, p20), viewCoord(xr, zmax, p00, p20)));
  b.x1 = std::fmax(std::fmax(viewCoord(xl, zmin, p00, p20), viewCoord(xl, zmax, p00, p20)),
                   std::fmax(viewCoord(xr, zmin, p00, p20), viewCoord(xr, zmax, p00, p20)));
  b.y0 = std::fmin(std::fmin(viewCoord(yb, zmin, p11, p21), viewCoord(yb, zmax, p11, p21)),
                   std::fmin(viewCoord(yt, zmin, p11, p21), viewCoord(yt, zmax, p11, p21)));
  b.y1 = std::fmax(std::fmax(viewCoord(yb, zmin, p11, p21), viewCoord(yb, zmax, p11, p21)),
                   std::fmax(viewCoord(yt, zmin, p11, p21), viewCoord(yt, zmax, p11, p21)));
  b.z0 = zmin;
  b.z1 = zmax;
  return b;
}

std::vector<ClusterBox> pixelBoxes(const float* depth, const std::vector<std::uint32_t>& cluster_of,
                                   std::uint32_t clusters, const gpu::CameraParams& cam) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::vector<ClusterBox> boxes(clusters, ClusterBox{inf, -inf, inf, -inf, inf, -inf});
  const float sx = 2.0f / float(cam.width), sy = 2.0f / float(cam.height);
  const float ix = 1.0f / cam.proj[0], iy = 1.0f / cam.proj[5], ox = cam.proj[8], oy = cam.proj[9];
  for (unsigned y = 0; y < cam.height; ++y) {
    const float fy = ((float(y) + 0.5f) * sy - 1.0f + oy) * iy;
    for (unsigned x = 0; x < cam.width; ++x) {
      const std::size_t p = std::size_t(y) * cam.width + x;
      const std::uint32_t c = cluster_of[p];
      if (c == kClusterInvalid) continue;
      const float z = gpu::linear_depth(depth[p], cam);
      const float fx = ((float(x) + 0.5f) * sx - 1.0f + ox) * ix;
      const float vx = z * fx, vy = z * fy;
      ClusterBox& b = boxes.at(c);
      b.x0 = std::fmin(b.x0, vx);
      b.x1 = std::fmax(b.x1, vx);
      b.y0 = std::fmin(b.y0, vy);
      b.y1 = std::fmax(b.y1, vy);
      b.z0 = std::fmin(b.z0, z);
      b.z1 = std::fmax(b.z1, z);
    }
  }
  for (ClusterBox& b : boxes) {
    const float ext = std::fmax(std::fmax(b.z1, std::fmax(std::fabs(b.x0), std::fabs(b.x1))),
                                std::fmax(std::fabs(b.y0), std::fabs(b.y1)));
    const float pad = ext * kClusterDepthEps, eps = kClusterDepthEps;
    b = {b.x0 - pad, b.x1 + pad, b.y0 - pad, b.y1 + pad, b.z0 - b.z0 * eps, b.z1 + b.z1 * eps};
  }
  return boxes;
}

ViewSphere viewSphere(const gpu::PointLight& l, const gpu::CameraParams& cam) {
  const float* m = cam.view;
  const float px = l.position_radius.x, py = l.position_radius.y, pz = l.position_radius.z;
  return {m[0] * px + m[4] * py + m[8] * pz + m[12] * 1.0f, m[1] * px + m[5] * py + m[9] * pz + m[13] * 1.0f,
          m[2] * px + m[6] * py + m[10] * pz + m[14] * 1.0f, l.position_radius.w};
}

bool sphereHitsCluster(const ViewSphere& s, const ClusterBox& b) {
  const float d = -s.z;
  const float dx = s.x - std::clamp(s.x, b.x0, b.x1), dy = s.y - std::clamp(s.y, b.y0, b.y1),
              dz = d - std::clamp(d, b.z0, b.z1);
  return dx * dx + dy * dy + dz * dz <= s.r * s.r * (1.0f + 4.0f * kClusterDepthEps);
}

std::vector<std::vector<std::uint32_t>> referenceAssign(const std::vector<ClusterBox>& boxes,
                                                        const std::vector<gpu::PointLight>& lights,
                                                        const gpu::CameraParams& cam) {
  std::vector<ViewSphere> spheres;
  spheres.reserve(lights.size());
  for (const auto& l : lights) spheres.push_back(viewSphere(l, cam));
  std::vector<std::vector<std::uint32_t>> out(boxes.size());
  for (std::size_t c = 0; c < boxes.size(); ++c)
    for (std::uint32_t i = 0; i < spheres.size(); ++i)
      if (sphereHitsCluster(spheres[i], boxes[c])) out[c].push_back(i);
  return out;
}

std::vector<std::vector<std::uint32_t>> referenceAssign(const std::vector<std::uint32_t>& unique_keys,
                                                        const std::vector<gpu::PointLight>& lights,
                                                        const gpu::CameraParams& cam, const ClusterGrid& g) {
  std::vector<ClusterBox> boxes;
  boxes.reserve(unique_keys.size());
  for (std::uint32_t key : unique_keys) boxes.push_back(clusterBox(key, cam, g));
  return referenceAssign(boxes, lights, cam);
}

}  // namespace ml
