#include "host/vct/VoxelViewTwin.hpp"

#include <algorithm>
#include <cmath>

namespace ml::vct {
namespace {

glm::vec3 meanAlbedo(const std::vector<gpu::VoxelAccum>& accum, unsigned edge, unsigned level, glm::ivec3 cell) {
  const int n = 1 << level;
  std::uint32_t sum[4] = {0, 0, 0, 0};
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::ivec3 p = cell * n + glm::ivec3(x, y, z);
        const auto& a = accum[unsigned(p.x) + edge * (unsigned(p.y) + edge * unsigned(p.z))];
        for (int c = 0; c < 4; ++c) sum[c] += a.albedo_count[c];
      }
  if (sum[3] == 0) return glm::vec3(0.0f);
  return glm::vec3(float(sum[0]), float(sum[1]), float(sum[2])) / (255.0f * float(sum[3]));
}

// voxel_view.comp's shade(): the kind's value of a voxel with opacity > 0.
glm::vec4 shade(const std::vector<gpu::VoxelAccum>& accum, unsigned edge, unsigned level, VoxelViewKind kind,
                glm::ivec3 cell, const gpu::ml_float4& v) {
  if (kind == VoxelViewKind::Albedo) return glm::vec4(meanAlbedo(accum, edge, level, cell), 1.0f);
  if (kind == VoxelViewKind::Radiance) return glm::vec4(v.x / v.w, v.y / v.w, v.z / v.w, 1.0f);
  return glm::vec4(v.w, v.w, v.w, 1.0f);
}

}  // namespace

PixelRay voxelViewRay(const VoxelViewCamera& camera, unsigned x, unsigned y) {
  const glm::mat4 inv_vp = glm::inverse(camera.proj * camera.view);
  const glm::vec3 eye = glm::vec3(glm::inverse(camera.view)[3]);
  const glm::vec2 ndc = (glm::vec2(float(x), float(y)) + 0.5f) / glm::vec2(float(camera.width), float(camera.height)) *
                            2.0f -
                        1.0f;
  const glm::vec4 p = inv_vp * glm::vec4(ndc, 0.5f, 1.0f);
  return {eye, glm::vec3(p) / p.w - eye};
}

glm::vec4 voxelViewPixelTwin(const std::vector<gpu::ml_float4>& radiance, const std::vector<gpu::VoxelAccum>& accum,
                             const gpu::VoxelGridParams& grid, VoxelViewKind kind, unsigned level,
                             const VoxelViewCamera& camera, unsigned x, unsigned y) {
  const PixelRay ray = voxelViewRay(camera, x, y);
  const unsigned e = grid.edge >> level;
  const unsigned offset = gpu::voxel_level_offset(grid.edge, level);
  const auto& g = grid.origin_voxel_size;
  const float size = g.w * float(1u << level);
  const glm::vec3 o = (ray.origin - glm::vec3(g.x, g.y, g.z)) / size;
  glm::vec3 d = ray.direction / size;
  for (int c = 0; c < 3; ++c)
    if (std::fabs(d[c]) < 1e-20f) d[c] = 1e-20f;
  const glm::vec3 inv = 1.0f / d;
  const glm::vec3 t0 = (glm::vec3(0.0f) - o) * inv, t1 = (glm::vec3(float(e)) - o) * inv;
  const glm::vec3 tlo = glm::min(t0, t1), thi = glm::max(t0, t1);
  const float tenter = std::max(std::max(tlo.x, tlo.y), tlo.z);
  const float tmin = std::max(tenter, 0.0f);
  const float tmax = std::min(std::min(thi.x, thi.y), thi.z);
  if (tmax < tmin) return glm::vec4(0.0f);
  const glm::ivec3 last(int(e) - 1);
  glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(o + d * tmin)), glm::ivec3(0), last);
  const glm::ivec3 stp(d.x > 0 ? 1 : -1, d.y > 0 ? 1 : -1, d.z > 0 ? 1 : -1);
  glm::vec3 next = (glm::vec3(cell + glm::max(stp, glm::ivec3(0))) - o) * inv;
  const glm::vec3 delta = glm::abs(inv);
  const unsigned first = tenter < 0.0f ? 1 : 0;  // the eye's own voxel is not shown
  for (unsigned i = 0; i < 3 * e + 1; ++i) {
    const gpu::ml_float4& v = radiance[offset + unsigned(cell.x) + e * (unsigned(cell.y) + e * unsigned(cell.z))];
    if (i >= first && v.w > 0.0f) return shade(accum, grid.edge, level, kind, cell, v);
    int axis = 2;
    if (next.x < next.y && next.x < next.z)
      axis = 0;
    else if (next.y < next.z)
      axis = 1;
    cell[axis] += stp[axis];
    next[axis] += delta[axis];
    if (cell[axis] < 0 || cell[axis] > last[axis]) break;
  }
  return glm::vec4(0.0f);
}

glm::vec4 voxelSlicePixelTwin(const std::vector<gpu::ml_float4>& radiance, const std::vector<gpu::ml_float4>& aniso,
                              const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& grid,
                              VoxelViewKind kind, unsigned level, const VoxelSlice& slice, unsigned width,
                              unsigned height, unsigned x, unsigned y) {
  const unsigned e = grid.edge >> level;
  const unsigned side = std::min(width, height);
  const unsigned lo_x = (width - side) / 2, lo_y = (height - side) / 2;
  if (x < lo_x || y < lo_y || x >= lo_x + side || y >= lo_y + side) return glm::vec4(0.0f);
  const int u = int((x - lo_x) * e / side), v = int((y - lo_y) * e / side);
  const int k = int(voxelSlicePlane(slice, e));
  const glm::ivec3 cell =
      slice.axis == 0 ? glm::ivec3(k, v, u) : (slice.axis == 1 ? glm::ivec3(u, k, v) : glm::ivec3(u, v, k));
  const unsigned i = unsigned(cell.x) + e * (unsigned(cell.y) + e * unsigned(cell.z));
  gpu::ml_float4 value = radiance[gpu::voxel_level_offset(grid.edge, level) + i];
  if (!aniso.empty() && level > 0) {
    glm::vec4 sum(0.0f);
    for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d) {
      const gpu::ml_float4& a = aniso[gpu::voxel_aniso_index(grid.edge, level, d, i)];
      sum += glm::vec4(a.x, a.y, a.z, a.w);
    }
    sum /= 6.0f;
    value = {sum.x, sum.y, sum.z, sum.w};
  }
  return value.w > 0.0f ? shade(accum, grid.edge, level, kind, cell, value) : glm::vec4(0.0f);
}

}  // namespace ml::vct
