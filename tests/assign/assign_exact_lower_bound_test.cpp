// The exact lower bound's kernel (kernels/assign/exact_lower_bound.cl) against its
// C++ twin (ml::boundAtPixel), and the twin's light grid against testing
// every light: random cameras, depths (background included), light sets of
// 0, 1, odd and duplicated lights with radii over several bands, odd sizes.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <random>

#include "host/assign/ExactLowerBound.hpp"
#include "host/compute/HostIo.hpp"
#include "host/scene/LightSet.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

std::vector<gpu::PointLight> randomLights(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<float> pos(-6.0f, 6.0f), col(0.0f, 1.0f), band(-5.0f, 3.0f);
  std::vector<gpu::PointLight> lights;
  for (std::size_t i = 0; i < n; ++i) {
    if (!lights.empty() && i % 5 == 3) {  // duplicates
      lights.push_back(lights[rng() % lights.size()]);
      continue;
    }
    float r = std::exp2(band(rng));  // radii over eight power-of-two bands
    if (i % 11 == 7) r = 0.0f;       // contains nothing
    if (i % 13 == 5) r = -r;         // the predicate squares it
    lights.push_back(makeLight({pos(rng), pos(rng), pos(rng)}, r, {col(rng), col(rng), col(rng)}));
  }
  return lights;
}

std::uint32_t boundByEveryLight(const std::vector<gpu::PointLight>& lights, const gpu::BoundParams& p, float depth,
                                unsigned x, unsigned y) {
  glm::vec3 P;
  if (!windowToWorld(depth, x, y, p, P)) return 0;
  std::uint32_t n = 0;
  for (const auto& l : lights) {
    const auto& L = l.position_radius;
    const float dx = L.x - P.x, dy = L.y - P.y, dz = L.z - P.z;
    if (dx * dx + dy * dy + dz * dz < L.w * L.w) ++n;
  }
  return n;
}

TEST(ExactLowerBound, KernelMatchesTwinAndTwinMatchesEveryLight) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto& rt = test::runtime();
  auto& q = rt.queue();
  ExactLowerBound bound(rt);
  const std::size_t light_counts[] = {0, 1, 2, 37, 300, 1001};
  const unsigned sizes[][2] = {{1, 1}, {7, 5}, {33, 17}, {64, 48}};
  std::uint64_t total = 0;
  for (std::size_t n : light_counts) {
    const auto lights = randomLights(rng, n);
    bound.setLights(q, lights);
    for (const auto& wh : sizes) {
      const unsigned w = wh[0], h = wh[1];
      std::uniform_real_distribution<float> u(-1.0f, 1.0f);
      const glm::vec3 eye(8 * u(rng), 8 * u(rng), 8 * u(rng));
      const glm::mat4 view = glm::lookAt(eye, glm::vec3(u(rng), u(rng), u(rng)), glm::vec3(0, 1, 0));
      const glm::mat4 proj = glm::perspective(glm::radians(50.0f + 20 * u(rng)), float(w) / float(h), 0.1f, 40.0f);
      const gpu::BoundParams p = boundParams(view, proj, w, h);
      std::vector<float> depth(std::size_t(w) * h);
      std::uniform_real_distribution<float> d01(0.0f, 1.0f);
      for (auto& d : depth) d = (rng() % 5 == 0) ? 1.0f : 0.9f + 0.1f * d01(rng) * 0.999f;
      cl::Buffer depth_buf = compute::upload(rt.context(), q, depth);
      cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(4, depth.size() * 4 + 64));
      compute::poison(q, out);
      bound.count(q, depth_buf, p, out);
      const auto got = compute::download<std::uint32_t>(q, out, depth.size() + 16);
      for (unsigned y = 0; y < h; ++y)
        for (unsigned x = 0; x < w; ++x) {
          const std::size_t i = std::size_t(y) * w + x;
          const std::uint32_t twin = boundAtPixel(bound.grid(), p, depth[i], x, y);
          ASSERT_EQ(got[i], twin) << "lights " << n << " size " << w << "x" << h << " pixel " << x << "," << y;
          ASSERT_EQ(twin, boundByEveryLight(lights, p, depth[i], x, y)) << "lights " << n << " pixel " << x << "," << y;
          total += twin;
        }
      for (std::size_t i = depth.size(); i < got.size(); ++i) ASSERT_EQ(got[i], 0xDEADBEEFu) << "wrote past the end";
    }
  }
  EXPECT_GT(total, 0u);  // the random frames do reach lights
}

TEST(ExactLowerBound, GridListsEachLightInFewCellsPerLevel) {
  std::mt19937_64 rng(test::freshSeed());
  const auto lights = randomLights(rng, 2000);
  const LightGrid g = buildLightGrid(lights);
  EXPECT_GE(g.levels.size(), 4u);  // eight bands of radii
  EXPECT_LE(g.entries.size(), 27 * lights.size());
  EXPECT_EQ(g.cell_start.back(), g.entries.size());
  EXPECT_TRUE(buildLightGrid({}).levels.empty());
}

}  // namespace
}  // namespace ml
