// Per-cluster light lists on the device: brute force against the C++
// reference (exactly), the BVH against brute force (as sets), with lights
// straddling the near plane, around the eye and huge; and conservativeness:
// every light whose sphere contains a pixel's surface point is in the list of
// that pixel's cluster.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "clustered_support.hpp"
#include "host/clustered/ClusterLightAssigner.hpp"
#include "host/clustered/ClusterUniquer.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

constexpr std::uint32_t kPoison = 0xDEADBEEFu;

struct Frame {
  ClusterGrid grid;
  std::vector<std::uint32_t> unique, cluster_of;
};

Frame clusters(ClusterUniquer& u, const test::ClusterCase& c, cl::Buffer& depth, unsigned tile) {
  auto& q = test::runtime().queue();
  Frame f;
  f.grid = ClusterGrid::make(c.cam(), tile);
  q.enqueueWriteBuffer(depth, CL_TRUE, 0, c.depth.size() * 4, c.depth.data());
  u.keys(q, depth, c.cam(), f.grid);
  const std::uint32_t n = u.unique(q, f.grid);
  f.unique.resize(n);
  f.cluster_of.resize(c.depth.size());
  if (n) q.enqueueReadBuffer(u.uniqueKeys(), CL_TRUE, 0, n * 4, f.unique.data());
  q.enqueueReadBuffer(u.clusterOf(), CL_TRUE, 0, c.depth.size() * 4, f.cluster_of.data());
  return f;
}

// Sorted list per cluster, with the range layout checked.
std::vector<std::vector<std::uint32_t>> assign(ClusterLightAssigner& a, ClusterUniquer& u, const test::ClusterCase& c,
                                               const Frame& f) {
  ClRuntime& rt = test::runtime();
  auto& q = rt.queue();
  const auto n = std::uint32_t(c.lights.size());
  cl::Buffer lights(rt.context(), CL_MEM_READ_ONLY, std::max<std::size_t>(32, n * 32));
  if (n) q.enqueueWriteBuffer(lights, CL_TRUE, 0, n * 32, c.lights.data());
  const auto clusters = std::uint32_t(f.unique.size());
  const std::uint32_t total = a.count(q, lights, n, c.cam(), f.grid, u.uniqueKeys(), clusters);
  cl::Buffer ranges(rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, clusters * 8));
  cl::Buffer indices(rt.context(), CL_MEM_READ_WRITE, total * 4 + 64);
  q.enqueueFillBuffer(ranges, kPoison, 0, std::max<std::size_t>(16, clusters * 8));
  q.enqueueFillBuffer(indices, kPoison, 0, total * 4 + 64);
  a.fill(q, ranges, indices);
  std::vector<gpu::LightRange> r(clusters);
  std::vector<std::uint32_t> idx(total + 16);
  if (clusters) q.enqueueReadBuffer(ranges, CL_TRUE, 0, clusters * 8, r.data());
  q.enqueueReadBuffer(indices, CL_TRUE, 0, idx.size() * 4, idx.data());
  for (std::size_t i = total; i < idx.size(); ++i) EXPECT_EQ(idx[i], kPoison) << "write past the list end";
  std::vector<std::vector<std::uint32_t>> lists(clusters);
  std::uint32_t offset = 0;
  for (std::uint32_t k = 0; k < clusters; ++k) {
    EXPECT_EQ(r[k].offset, offset) << "cluster " << k;
    offset += r[k].count;
    if (r[k].offset + r[k].count > total) {
      ADD_FAILURE() << "cluster " << k << " out of range";
      continue;
    }
    lists[k].assign(idx.begin() + r[k].offset, idx.begin() + r[k].offset + r[k].count);
    std::sort(lists[k].begin(), lists[k].end());
  }
  EXPECT_EQ(offset, total);
  return lists;
}

TEST(ClusteredAssign, BruteMatchesReferenceAndBvhMatchesBrute) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClRuntime& rt = test::runtime();
  ClusterUniquer u(rt, UniqueMethod::PageTable);
  ClusterLightAssigner brute(rt, ClusterAssignMethod::Brute), bvh(rt, ClusterAssignMethod::Bvh);
  // Light counts give BVHs of 1 (< 32 lights), 2 and 3 levels, and none at all.
  for (auto [w, h, tile, n] : {std::tuple{160u, 96u, 32u, 20u}, std::tuple{203u, 117u, 16u, 3000u},
                               std::tuple{64u, 48u, 32u, 40000u}, std::tuple{50u, 30u, 8u, 0u}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(tile) + " lights " +
                 std::to_string(n));
    const auto c = test::randomClusterCase(rng, w, h, n);
    cl::Buffer depth(rt.context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
    const Frame f = clusters(u, c, depth, tile);
    ASSERT_GT(f.unique.size(), 0u);
    const auto ref = referenceAssign(f.unique, c.lights, c.cam(), f.grid);
    const auto b = assign(brute, u, c, f);
    const auto t = assign(bvh, u, c, f);
    std::size_t pairs = 0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
      ASSERT_EQ(b[k], ref[k]) << "brute, cluster " << k;
      ASSERT_EQ(t[k], ref[k]) << "bvh, cluster " << k;
      pairs += ref[k].size();
    }
    if (n > 0) {
      EXPECT_GT(pairs, 0u);
    }
    if (n == 40000) {
      EXPECT_EQ(bvh.bvhLevels(), 3u);
    }

    // Conservative: a light containing a pixel's surface point is in its cluster's list.
    const glm::mat4 inv = glm::inverse(c.camera.projection(float(w) / float(h)) * c.camera.view());
    for (unsigned y = 0; y < h; y += 3)
      for (unsigned x = 0; x < w; x += 3) {
        const std::size_t p = std::size_t(y) * w + x;
        if (c.depth[p] >= 1.0f) continue;
        const glm::vec4 ndc{(x + 0.5f) / w * 2 - 1, (y + 0.5f) / h * 2 - 1, c.depth[p] * 2 - 1, 1};
        glm::vec4 wp = inv * ndc;
        wp /= wp.w;
        const auto& list = t[f.cluster_of[p]];
        for (std::uint32_t i = 0; i < n; ++i) {
          const auto& l = c.lights[i].position_radius;
          const glm::vec3 d = glm::vec3(wp) - glm::vec3(l.x, l.y, l.z);
          if (glm::dot(d, d) < l.w * l.w * 0.999f) {
            ASSERT_TRUE(std::binary_search(list.begin(), list.end(), i)) << "pixel " << x << "," << y << " light " << i;
          }
        }
      }
  }
}

}  // namespace
}  // namespace ml
