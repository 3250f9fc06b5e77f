// Voxel light injection (kernels/vct_inject.cl through vct::VoxelInjector),
// both kernel shapes:
//  - brute force equals the C++ twin (host/vct/InjectTwin.hpp) on random
//    accumulation volumes and random lights: 0 and 1 light, lights outside
//    the grid, radii spanning the whole grid, voxels whose normals cancel.
//  - through the hashed structure's lists equals brute force: only the
//    summation order differs.
//  - the OpenCL port of the hashed lookup returns LinklessOctree::lookup()'s
//    range and octant for random points in and around the octree.
//  - a known value pins the shading model itself.
// Tolerance: bit-exact where the device divides and takes square roots
// correctly rounded (support/FpTolerance.hpp); elsewhere (and always for the
// hashed order) |got - want| <= 1e-5 * S per component, S = albedo * 0.9 *
// sum_i I_i * sqrt(att_i): a few ulps on each light's cosine and distance
// move its term by at most that much, since an error e in d / r moves att by
// about 2 sqrt(att) e. Outputs are poisoned first.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/hashed/HashedStructure.hpp"
#include "host/scene/LightSet.hpp"
#include "host/shared/shading_model.h"
#include "host/vct/InjectTwin.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;

float uni(std::mt19937_64& rng, float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }

gpu::VoxelGridParams randomGrid(unsigned edge, std::mt19937_64& rng) {
  gpu::VoxelGridParams g{};
  g.origin_voxel_size = {uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, 0.05f, 1.0f)};
  g.edge = edge;
  g.levels = 1;
  return g;
}

// About half the voxels filled; 1 in 10 filled ones with a zero normal sum.
std::vector<gpu::VoxelAccum> randomAccum(unsigned edge, std::mt19937_64& rng) {
  std::vector<gpu::VoxelAccum> a(std::size_t(edge) * edge * edge, gpu::VoxelAccum{});
  for (auto& v : a) {
    if (rng() % 2) continue;
    const unsigned count = 1 + rng() % 40;
    v.albedo_count[3] = count;
    for (int c = 0; c < 3; ++c) v.albedo_count[c] = unsigned(rng() % (255 * count + 1));
    if (rng() % 10 == 0) continue;
    for (int c = 0; c < 3; ++c) v.normal_sum[c] = int(rng() % (2049 * count)) - int(1024 * count);
  }
  return a;
}

// Lights around the grid (some outside it); every 5th reaches across it all.
std::vector<gpu::PointLight> randomLights(std::size_t n, const gpu::VoxelGridParams& g, std::mt19937_64& rng) {
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
std::vector<F4> toleranceScale(const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& g,
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
std::string compare(const std::vector<F4>& got, const std::vector<F4>& want, const std::vector<F4>& scale,
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

struct Case {
  std::vector<gpu::VoxelAccum> accum;
  gpu::VoxelGridParams grid;
  std::vector<gpu::PointLight> lights;
};

class VctInject : public ::testing::TestWithParam<KernelShape> {
 protected:
  // Brute force and hashed on the device for `c`, each against the twin.
  void check(const Case& c) {
    auto& rt = test::runtime();
    auto& q = rt.queue();
    const auto want = injectTwin(c.accum, c.grid, c.lights);
    const auto scale = toleranceScale(c.accum, c.grid, c.lights);
    cl::Buffer accum = compute::upload(rt.context(), q, c.accum);
    cl::Buffer lights = compute::upload(rt.context(), q, c.lights);
    cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, want.size() * 16);
    compute::poison(q, out);
    injector_.brute(q, c.grid, accum, lights, c.lights.size(), out);
    EXPECT_EQ(compare(compute::download<F4>(q, out, want.size()), want, scale, test::exactDivideSqrt()), "")
        << "brute force";
    if (c.lights.empty()) return;  // the hashed structure needs lights to bound
    hashed::HashedStructure hs(hashed::HashedConfig{});
    hs.build(c.lights);
    lists_.upload(q, hs.linkless());
    compute::poison(q, out);
    injector_.hashed(q, c.grid, accum, lights, c.lights.size(), lists_, out);
    EXPECT_EQ(compare(compute::download<F4>(q, out, want.size()), want, scale, false), "") << "hashed lists";
  }
  compute::ComputeEnv env_{test::runtime()};
  VoxelInjector injector_{env_, compute::Options{.shape = GetParam()}};
  HashedListsCl lists_{env_};
};

TEST_P(VctInject, MatchesTwinOnRandomVolumes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const unsigned largest = test::smallTests() ? 8 : 32;
  for (unsigned edge = 1; edge <= largest; edge *= 2)
    for (std::size_t lights : {0, 1, 2, 7, 300}) {
      SCOPED_TRACE("edge=" + std::to_string(edge) + " lights=" + std::to_string(lights));
      Case c{randomAccum(edge, rng), randomGrid(edge, rng), {}};
      c.lights = randomLights(lights, c.grid, rng);
      check(c);
    }
}

// One light far outside the grid reaching none of it, one outside reaching in.
TEST_P(VctInject, LightsOutsideTheGrid) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  Case c{randomAccum(8, rng), randomGrid(8, rng), {}};
  const glm::vec3 o(c.grid.origin_voxel_size.x, c.grid.origin_voxel_size.y, c.grid.origin_voxel_size.z);
  const float size = 8 * c.grid.origin_voxel_size.w;
  c.lights = {makeLight(o - glm::vec3(10 * size), size, glm::vec3(1)),
              makeLight(o + glm::vec3(1.2f * size, 0.5f * size, 0.5f * size), 0.6f * size, glm::vec3(1, 0.5f, 0.25f))};
  check(c);
}

// One voxel, one light straight above it: radiance = albedo * 0.9 * I * att.
TEST_P(VctInject, KnownValue) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<gpu::VoxelAccum> a(1, gpu::VoxelAccum{});
  a[0].albedo_count[0] = 255;
  a[0].albedo_count[2] = 51;
  a[0].albedo_count[3] = 1;
  a[0].normal_sum[1] = 1024;
  gpu::VoxelGridParams g{};
  g.origin_voxel_size = {0, 0, 0, 1};
  g.edge = 1;
  g.levels = 1;
  // d = 2, r = 4: att = (1 - 0.5)^2 = 0.25; cos = 1.
  const std::vector<gpu::PointLight> l = {makeLight({0.5f, 2.5f, 0.5f}, 4.0f, {1.0f, 0.5f, 1.0f})};
  cl::Buffer accum = compute::upload(rt.context(), q, a), lights = compute::upload(rt.context(), q, l);
  cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, 16);
  compute::poison(q, out);
  injector_.brute(q, g, accum, lights, 1, out);
  const F4 v = compute::download<F4>(q, out, 1)[0];
  EXPECT_NEAR(v.x, 0.225f, 1e-6f);
  EXPECT_EQ(v.y, 0.0f);
  EXPECT_NEAR(v.z, 0.045f, 1e-6f);
  EXPECT_EQ(v.w, 1.0f);
}

TEST_P(VctInject, HashedLookupPortMatchesHost) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  gpu::VoxelGridParams g = randomGrid(16, rng);
  const auto lights = randomLights(test::smallTests() ? 50 : 2000, g, rng);
  hashed::HashedStructure hs(hashed::HashedConfig{});
  hs.build(lights);
  const auto& b = hs.linkless().bounds();
  const glm::vec3 lo = b.origin_f, hi = lo + glm::vec3(float(1u << b.depth) / b.cell_scale);
  // Half the points in the grid's box, where every point lies in one of the
  // lights spanning the grid; half anywhere around the octree's cube.
  const glm::vec3 go(g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z);
  const glm::vec3 gs(g.origin_voxel_size.w * float(g.edge));
  std::vector<F4> points;
  for (int i = 0; i < (test::smallTests() ? 2000 : 20000); ++i) {
    const glm::vec3 t(uni(rng, -0.1f, 1.1f), uni(rng, -0.1f, 1.1f), uni(rng, -0.1f, 1.1f));
    const glm::vec3 p = i % 2 ? lo + t * (hi - lo) : go + t * gs;
    points.push_back({p.x, p.y, p.z, 0});
  }
  auto& q = test::runtime().queue();
  lists_.upload(q, hs.linkless());
  const auto got = lists_.lookup(q, points);
  std::size_t listed = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto want = hs.linkless().lookup({points[i].x, points[i].y, points[i].z});
    ASSERT_EQ(got[i].offset, want.offset) << "point " << i;
    ASSERT_EQ(got[i].count, want.count) << "point " << i;
    if (want.count) {
      ASSERT_EQ(got[i].octant, want.octant) << "point " << i;
    }
    listed += want.count != 0;
  }
  EXPECT_GT(listed, points.size() / 4) << "too few points with lists: the test would prove little";
  EXPECT_LT(listed, points.size()) << "no point without a list: the outside was not probed";
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctInject, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml::vct
