#pragma once
// Random voxel injection cases and the injection tolerance, shared by the
// injection tests (vct_inject_test.cpp, vct_lists_update_test.cpp): random
// grids, accumulation volumes and lights around a grid; S, the per-voxel
// tolerance scale (albedo * 0.9 * sum_i I_i * sqrt(att_i), see
// vct_inject_test.cpp's header); compare() against it or bit for bit.
#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host/scene/LightSet.hpp"
#include "host/shared/shading_model.h"
#include "host/shared/voxel_types.h"
#include "host/vct/InjectTwin.hpp"

namespace ml::vct::inject_case {

using F4 = gpu::ml_float4;

inline float uni(std::mt19937_64& rng, float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }

inline gpu::VoxelGridParams randomGrid(unsigned edge, std::mt19937_64& rng) {
  gpu::VoxelGridParams g{};
  g.origin_voxel_size = {uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, 0.05f, 1.0f)};
  g.edge = edge;
  g.levels = 1;
  return g;
}

// 1 in `fill` voxels filled (about half by default); 1 in 10 filled ones
// with a zero normal sum.
inline std::vector<gpu::VoxelAccum> randomAccum(unsigned edge, std::mt19937_64& rng, unsigned fill = 2) {
  std::vector<gpu::VoxelAccum> a(std::size_t(edge) * edge * edge, gpu::VoxelAccum{});
  for (auto& v : a) {
    if (rng() % fill) continue;
    const unsigned count = 1 + rng() % 40;
    v.albedo_count[3] = count;
    for (int c = 0; c < 3; ++c) v.albedo_count[c] = unsigned(rng() % (255 * count + 1));
    if (rng() % 10 == 0) continue;
    for (int c = 0; c < 3; ++c) v.normal_sum[c] = int(rng() % (2049 * count)) - int(1024 * count);
  }
  return a;
}

// Lights around the grid (some outside it); every 5th reaches across it all.
inline std::vector<gpu::PointLight> randomLights(std::size_t n, const gpu::VoxelGridParams& g, std::mt19937_64& rng) {
  const float size = g.origin_voxel_size.w * float(g.edge);
  const glm::vec3 o(g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z);
  std::vector<gpu::PointLight> out;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 p = o + glm::vec3(uni(rng, -0.5f, 1.5f), uni(rng, -0.5f, 1.5f), uni(rng, -0.5f, 1.5f)) * size;
    const float r = i % 5 == 4 ? 3.0f * size : uni(rng, 0.02f, 0.6f) * size;
    out.push_back(makeLight(p, r, glm::vec3(uni(rng, 0, 1), uni(rng, 0, 1), uni(rng, 0, 1))));
  }
  return out;
}

// S of the header, per voxel and component.
inline std::vector<F4> toleranceScale(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g,
                               const std::vector<gpu::PointLight>& lights) {
  std::vector<F4> s(accum.size(), F4{0, 0, 0, 0});
  for (unsigned i = 0; i < accum.size(); ++i) {
    Surfel v;
    if (!resolveVoxel(accum[i], i, g, v)) continue;
    double acc[3] = {0, 0, 0};
    for (const auto& l : lights) {
      const auto& pr = l.position_radius;
      const double att = gpu::ml_light_weight(pr.x, pr.y, pr.z, pr.w, v.p[0], v.p[1], v.p[2], 0, 0, 0);
      acc[0] += l.color.x * std::sqrt(att);
      acc[1] += l.color.y * std::sqrt(att);
      acc[2] += l.color.z * std::sqrt(att);
    }
    s[i] = {float(v.albedo[0] * 0.9 * acc[0]), float(v.albedo[1] * 0.9 * acc[1]), float(v.albedo[2] * 0.9 * acc[2]), 0};
  }
  return s;
}

// "" when every voxel matches, else the first mismatch.
inline std::string compare(const std::vector<F4>& got, const std::vector<F4>& want, const std::vector<F4>& scale,
                    bool exact) {
  for (std::size_t i = 0; i < want.size(); ++i) {
    const float g[4] = {got[i].x, got[i].y, got[i].z, got[i].w}, w[4] = {want[i].x, want[i].y, want[i].z, want[i].w};
    const float s[4] = {scale[i].x, scale[i].y, scale[i].z, 0};
    for (int c = 0; c < 4; ++c) {
      const bool ok = exact ? std::memcmp(&g[c], &w[c], 4) == 0 : std::fabs(g[c] - w[c]) <= 1e-5f * s[c];
      if (!ok)
        return "voxel " + std::to_string(i) + " component " + std::to_string(c) + ": got " + std::to_string(g[c]) +
               " want " + std::to_string(w[c]) + " (scale " + std::to_string(s[c]) + ")";
    }
  }
  return "";
}

}  // namespace ml::vct::inject_case
