// The voxel-shadow march's empty-space skipping, both kernel shapes:
//  - the empty-space distance volume (kernels/vct/vct_occupancy.cl through
//    vct::VoxelOccupancy) equals its C++ twin (host/vct/OccupancyTwin.hpp)
//    byte for byte on random volumes of edges 1, 2, odd and 2^k (+-1), empty,
//    full, sparse and dense, the buffer poisoned before each build; the twin
//    equals the definition (brute force over voxel pairs) on small grids;
//  - the skipping march (VoxelInjector's march(), VCT_SHADOW_SKIP) decides
//    exactly as the plain march on the device (skip_empty = false) for every
//    query, and as the plain C++ twin (InjectTwin's voxelVisibility()) where
//    the device divides correctly: random sparse and dense volumes, surfels
//    anywhere in the grid, lights inside, outside and on the grid's faces,
//    rays along the axes and the diagonals and random ones;
//  - it skips: on an empty grid and a sparse one it looks at a small part of
//    the samples the plain march tests (the plain probe's count equals the
//    twin's, so the counter counts what it says).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <glm/glm.hpp>
#include <random>
#include <string>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/shared/voxel_occupancy.h"
#include "host/vct/InjectTwin.hpp"
#include "host/vct/OccupancyTwin.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "host/vct/VoxelOccupancy.hpp"
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;

float uni(std::mt19937_64& rng, float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }

// Filled with probability 1 / fill (0: empty, 1: full); some filled 4^3
// blocks too when `blocks`, so that whole bricks are full next to empty ones.
std::vector<gpu::VoxelAccum> volume(unsigned edge, unsigned fill, bool blocks, std::mt19937_64& rng) {
  std::vector<gpu::VoxelAccum> a(std::size_t(edge) * edge * edge, gpu::VoxelAccum{});
  for (auto& v : a) v.albedo_count[3] = fill && rng() % fill == 0 ? 1 + unsigned(rng() % 9) : 0;
  if (blocks)
    for (unsigned b = 0; b < 1 + edge / 8; ++b) {
      const unsigned x0 = rng() % edge, y0 = rng() % edge, z0 = rng() % edge;
      for (unsigned z = z0; z < std::min(edge, z0 + 4); ++z)
        for (unsigned y = y0; y < std::min(edge, y0 + 4); ++y)
          for (unsigned x = x0; x < std::min(edge, x0 + 4); ++x) a[x + edge * (y + std::size_t(edge) * z)].albedo_count[3] = 1;
    }
  return a;
}

class VctOccupancy : public ::testing::TestWithParam<KernelShape> {};

// The definition itself, by brute force over every voxel pair (small grids).
std::vector<std::uint8_t> distanceByDefinition(const std::vector<gpu::VoxelAccum>& a, unsigned e) {
  std::vector<std::uint8_t> d(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    unsigned best = ML_OCC_MAX_DISTANCE;
    for (std::size_t u = 0; u < a.size(); ++u) {
      if (a[u].albedo_count[3] == 0) continue;
      const auto diff = [&](std::size_t p, std::size_t q) { return unsigned(p > q ? p - q : q - p); };
      best = std::min(best, std::max({diff(i % e, u % e), diff(i / e % e, u / e % e), diff(i / e / e, u / e / e)}));
    }
    d[i] = std::uint8_t(best);
  }
  return d;
}

TEST_P(VctOccupancy, MatchesTwinOnRandomVolumes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto& rt = test::runtime();
  auto& q = rt.queue();
  VoxelOccupancy occ(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  std::vector<unsigned> edges = {1, 2, 3, 4, 5, 7, 8, 15, 16, 17, 31, 32, 33};
  if (!test::smallTests()) edges.insert(edges.end(), {63, 64, 65});
  std::size_t far = 0;  // voxels at the clamp: the early stop and the clamp both ran
  for (unsigned edge : edges)
    for (unsigned fill : {0u, 1u, 2u, 60u, 3000u}) {
      SCOPED_TRACE("edge=" + std::to_string(edge) + " fill=1/" + std::to_string(fill));
      const auto a = volume(edge, fill, fill > 2 && rng() % 2, rng);
      const auto want = occupancyTwin(a, edge);
      if (edge <= 9) {
        ASSERT_EQ(want, distanceByDefinition(a, edge)) << "the twin misses the definition";
      }
      cl::Buffer accum = compute::upload(rt.context(), q, a);
      if (occ.edge()) {
        cl::Buffer old = occ.buffer();
        compute::poison(q, old);
      }
      occ.build(q, edge, accum);
      ASSERT_EQ(compute::download<std::uint8_t>(q, occ.buffer(), want.size()), want);
      for (std::uint8_t d : want) far += d == ML_OCC_MAX_DISTANCE;
    }
  EXPECT_GT(far, 0u);
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctOccupancy, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

// Queries of the march: surfels at voxel centres with unit or zero normals,
// lights of the kinds the header lists, in pn / lp as VoxelInjector::march().
struct Queries {
  std::vector<F4> pn, lp;
  std::vector<Surfel> surfels;
};

glm::vec3 unitOrZero(std::mt19937_64& rng) {
  if (rng() % 8 == 0) return glm::vec3(0);
  if (rng() % 4 == 0) {  // along an axis, as walls' normals are
    glm::vec3 n(0);
    n[rng() % 3] = rng() % 2 ? 1.0f : -1.0f;
    return n;
  }
  glm::vec3 n(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1));
  return glm::length(n) > 1e-3f ? glm::normalize(n) : glm::vec3(0, 1, 0);
}

// A light for surfel centre `p` in a grid of corner `o` and size `size`.
glm::vec3 lightFor(const glm::vec3& p, const glm::vec3& o, float size, float h, std::mt19937_64& rng) {
  const auto in = [&](float lo, float hi) {
    return o + glm::vec3(uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)) * size;
  };
  switch (rng() % 6) {
    case 0: return in(0, 1);      // inside
    case 1: return in(-1.5f, 2.5f);  // mostly outside
    case 2: {                     // on a face of the grid
      glm::vec3 l = in(0, 1);
      const int axis = int(rng() % 3);
      l[axis] = o[axis] + (rng() % 2 ? size : 0.0f);
      return l;
    }
    case 3: {  // along an axis, a whole or a random number of voxels away
      glm::vec3 l = p;
      l[rng() % 3] += (rng() % 2 ? 1.0f : -1.0f) * (rng() % 2 ? float(1 + rng() % 40) * h : uni(rng, 0, 1.5f) * size);
      return l;
    }
    case 4: {  // along a diagonal
      const glm::vec3 dir(rng() % 2 ? 1.0f : -1.0f, rng() % 2 ? 1.0f : -1.0f, rng() % 2 ? 1.0f : -1.0f);
      return p + dir * (rng() % 2 ? float(1 + rng() % 40) * h : uni(rng, 0, 1.5f) * size);
    }
    default: return p + glm::vec3(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)) * (2.0f * size);
  }
}

Queries randomQueries(const gpu::VoxelGridParams& g, std::size_t n, std::mt19937_64& rng) {
  const float h = g.origin_voxel_size.w, size = h * float(g.edge);
  const glm::vec3 o(g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z);
  Queries qs;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 v(float(rng() % g.edge), float(rng() % g.edge), float(rng() % g.edge));
    Surfel s{};
    const glm::vec3 p = o + (v + 0.5f) * h, nrm = unitOrZero(rng), l = lightFor(p, o, size, h, rng);
    for (int c = 0; c < 3; ++c) s.p[c] = p[c], s.n[c] = nrm[c];
    qs.surfels.push_back(s);
    qs.pn.push_back({p.x, p.y, p.z, 0});
    qs.pn.push_back({nrm.x, nrm.y, nrm.z, 0});
    qs.lp.push_back({l.x, l.y, l.z, 0});
  }
  return qs;
}

class VctShadowMarch : public ::testing::TestWithParam<KernelShape> {
 protected:
  compute::ComputeEnv env_{test::runtime()};
  VoxelInjector skipping_{env_, compute::Options{.shape = GetParam()}, true};
  VoxelInjector plain_{env_, compute::Options{.shape = GetParam()}, true, false};
};

TEST_P(VctShadowMarch, SkippingEqualsThePlainMarch) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const unsigned largest = test::smallTests() ? 16 : 64;
  const std::size_t n = test::smallTests() ? 300 : 3000;
  std::size_t seen = 0, hidden = 0, total = 0;
  for (unsigned edge = 1; edge <= largest; edge *= 2)
    for (unsigned fill : {0u, 2u, 9u, 80u, 1500u}) {
      SCOPED_TRACE("edge=" + std::to_string(edge) + " fill=1/" + std::to_string(fill));
      gpu::VoxelGridParams g{};
      g.origin_voxel_size = {uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, -10, 10), uni(rng, 0.05f, 1.0f)};
      if (rng() % 3 == 0) g.origin_voxel_size = {0, 0, 0, 1};  // faces on whole numbers: exact ties
      g.edge = edge;
      g.levels = 1;
      const auto a = volume(edge, fill, fill > 2, rng);
      const Queries qs = randomQueries(g, n, rng);
      cl::Buffer accum = compute::upload(rt.context(), q, a);
      const auto fast = skipping_.march(q, g, accum, qs.pn, qs.lp), slow = plain_.march(q, g, accum, qs.pn, qs.lp);
      for (std::size_t i = 0; i < n; ++i) {
        SCOPED_TRACE("query " + std::to_string(i));
        ASSERT_EQ(fast[i].visible, slow[i].visible) << "the skipping march decided otherwise than the plain one";
        const float lp[3] = {qs.lp[i].x, qs.lp[i].y, qs.lp[i].z};
        unsigned tested = 0;
        const bool twin = voxelVisibility(a, g, qs.surfels[i], lp, &tested) > 0.0f;
        if (test::exactDivideSqrt()) {
          ASSERT_EQ(slow[i].visible, twin) << "the plain march differs from its twin";
          ASSERT_EQ(slow[i].tested, tested) << "the plain march's sample count differs from its twin's";
        }
        ASSERT_LE(fast[i].tested, slow[i].tested) << "skipping looked at more samples";
        (twin ? seen : hidden) += 1;
        ++total;
      }
    }
  EXPECT_GT(seen, total / 10) << "too few visible pairs: the test would prove little";
  EXPECT_GT(hidden, total / 10) << "too few hidden pairs: the test would prove little";
}

// Far fewer samples looked at where the space is empty: an empty grid and
// one with a few scattered voxels, lights all around.
TEST_P(VctShadowMarch, SkipsEmptySpace) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const unsigned edge = test::smallTests() ? 16 : 64;
  for (unsigned fill : {0u, 4000u}) {
    SCOPED_TRACE("fill=1/" + std::to_string(fill));
    gpu::VoxelGridParams g{{0, 0, 0, 0.25f}, edge, 1, 0, 0};
    const auto a = volume(edge, fill, false, rng);
    const Queries qs = randomQueries(g, 2000, rng);
    cl::Buffer accum = compute::upload(rt.context(), q, a);
    const auto fast = skipping_.march(q, g, accum, qs.pn, qs.lp), slow = plain_.march(q, g, accum, qs.pn, qs.lp);
    std::uint64_t looked = 0, plain = 0;
    for (std::size_t i = 0; i < fast.size(); ++i) {
      ASSERT_EQ(fast[i].visible, slow[i].visible) << "query " << i;
      looked += fast[i].tested;
      plain += slow[i].tested;
    }
    std::printf("shadow march, %u^3, fill 1/%u: %llu samples looked at of %llu\n", edge, fill,
                static_cast<unsigned long long>(looked), static_cast<unsigned long long>(plain));
    EXPECT_LT(looked * 5, plain) << "the march skipped less than 4/5 of the samples in near-empty space";
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctShadowMarch, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml::vct
