#include "host/vct/InjectTwin.hpp"

#include <cmath>
#include <stdexcept>

#include "host/shared/shading_model.h"

namespace ml::vct {

bool resolveVoxel(const gpu::VoxelAccum& a, unsigned i, const gpu::VoxelGridParams& g, Surfel& s) {
  if (a.albedo_count[3] == 0) return false;
  const float denom = float(a.albedo_count[3]) * float(ML_VOXEL_ALBEDO_SCALE);
  for (int c = 0; c < 3; ++c) s.albedo[c] = float(a.albedo_count[c]) / denom;
  const float nx = float(a.normal_sum[0]), ny = float(a.normal_sum[1]), nz = float(a.normal_sum[2]);
  const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
  const float n[3] = {nx, ny, nz};
  for (int c = 0; c < 3; ++c) s.n[c] = len > 0.0f ? n[c] / len : 0.0f;
  const gpu::VoxelWindow w = gpu::voxel_window(g, i);
  const unsigned xyz[3] = {w.x, w.y, w.z};
  const float o[3] = {g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z};
  const gpu::VoxelCorner k = gpu::voxel_corner(g);
  const int corner[3] = {k.x, k.y, k.z};
  for (int c = 0; c < 3; ++c)
    s.p[c] = g.wrap ? (float(corner[c] + int(xyz[c])) + 0.5f) * g.origin_voxel_size.w  // lattice: kernel's bits
                    : o[c] + (float(xyz[c]) + 0.5f) * g.origin_voxel_size.w;
  return true;
}

float voxelVisibility(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g, const Surfel& s,
                      const float lp[3], unsigned* tested) {
  const float h = g.origin_voxel_size.w;
  const float o[3] = {g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z};
  float a[3], d[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = s.p[c] + s.n[c] * h;
    d[c] = lp[c] - a[c];
  }
  const float span = std::fmax(std::fabs(d[0]), std::fmax(std::fabs(d[1]), std::fabs(d[2])));
  const auto steps = static_cast<unsigned>(std::ceil(2.0f * span / h));
  const auto edge = float(g.edge);
  if (tested) *tested = steps;
  for (unsigned k = 0; k < steps; ++k) {
    const float t = (float(k) + 0.5f) / float(steps);
    float v[3];  // floored voxel coordinates, compared in float as the kernel does
    for (int c = 0; c < 3; ++c) v[c] = std::floor((a[c] + d[c] * t - o[c]) / h);
    if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] >= edge || v[1] >= edge || v[2] >= edge) continue;
    const std::size_t i = (std::size_t(v[2]) * g.edge + std::size_t(v[1])) * g.edge + std::size_t(v[0]);
    if (accum[i].albedo_count[3] != 0) {
      if (tested) *tested = k + 1;
      return 0.0f;
    }
  }
  return 1.0f;
}

std::vector<gpu::ml_float4> injectTwin(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g,
                                       const std::vector<gpu::PointLight>& lights, bool shadows) {
  const std::size_t n = std::size_t(g.edge) * g.edge * g.edge;
  if (accum.size() < n) throw std::invalid_argument("injectTwin: accumulation buffer smaller than the grid");
  std::vector<gpu::ml_float4> out(n, gpu::ml_float4{0, 0, 0, 0});
  for (unsigned i = 0; i < n; ++i) {
    Surfel s;
    if (!resolveVoxel(accum[i], i, g, s)) continue;
    float acc[3] = {0, 0, 0};
    for (const gpu::PointLight& l : lights) {
      const auto& pr = l.position_radius;
      float w = gpu::ml_light_weight(pr.x, pr.y, pr.z, pr.w, s.p[0], s.p[1], s.p[2], s.n[0], s.n[1], s.n[2]);
      const float lp[3] = {pr.x, pr.y, pr.z};
      if (shadows && w > 0.0f) w = w * voxelVisibility(accum, g, s, lp);
      acc[0] = acc[0] + l.color.x * w;
      acc[1] = acc[1] + l.color.y * w;
      acc[2] = acc[2] + l.color.z * w;
    }
    out[i] = {s.albedo[0] * (ML_SHADE_DIRECT * acc[0]), s.albedo[1] * (ML_SHADE_DIRECT * acc[1]),
              s.albedo[2] * (ML_SHADE_DIRECT * acc[2]), 1.0f};
  }
  return out;
}

}  // namespace ml::vct
