// Per-cluster light lists on the device: brute force against the C++
// reference (exactly), the BVH against brute force (as sets), with lights
// straddling the near plane, around the eye and huge; and conservativeness:
// every light whose sphere contains a pixel's surface point is in the list of
// that pixel's cluster. Both bounds: the sub-frustum boxes and the explicit
// boxes of the clusters' pixels (device boxes bit for bit against the C++
// reduction, fewer list entries in all than the sub-frustum boxes). Every
// test runs in both kernel shapes, and the GPU shape's boxes, records and
// leaves equal the CPU shape's exactly (same order).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "clustered_support.hpp"
#include "host/clustered/ClusterLightAssigner.hpp"
#include "host/clustered/ClusterUniquer.hpp"
#include "host/util/Error.hpp"
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/DepthPoints.hpp"
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

// The raw outputs of one count() + fill(), for comparing shapes.
struct RawLists {
  std::vector<gpu::LightRange> ranges;
  std::vector<std::uint32_t> records, leaf_lights;
};

// Sorted list per cluster, expanded from the hit records, with the range and
// record layout checked. pixels: explicit bounds. raw: the outputs as they are.
std::vector<std::vector<std::uint32_t>> assign(ClusterLightAssigner& a, ClusterUniquer& u, const test::ClusterCase& c,
                                               const Frame& f, const ClusterPixels* pixels, RawLists* raw = nullptr) {
  ClRuntime& rt = test::runtime();
  auto& q = rt.queue();
  const auto n = std::uint32_t(c.lights.size());
  cl::Buffer lights(rt.context(), CL_MEM_READ_ONLY, std::max<std::size_t>(32, n * 32));
  if (n) q.enqueueWriteBuffer(lights, CL_TRUE, 0, n * 32, c.lights.data());
  const auto clusters = std::uint32_t(f.unique.size());
  const std::uint32_t total = a.count(q, lights, n, c.cam(), f.grid, u.uniqueKeys(), clusters, nullptr, pixels);
  const std::size_t slots = a.leafLightSlots();
  cl::Buffer ranges(rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, clusters * 8));
  cl::Buffer records(rt.context(), CL_MEM_READ_WRITE, total * 8 + 64);
  cl::Buffer leaf_lights(rt.context(), CL_MEM_READ_WRITE, slots * 4 + 64);
  q.enqueueFillBuffer(ranges, kPoison, 0, std::max<std::size_t>(16, clusters * 8));
  q.enqueueFillBuffer(records, kPoison, 0, total * 8 + 64);
  q.enqueueFillBuffer(leaf_lights, kPoison, 0, slots * 4 + 64);
  a.fill(q, ranges, records, leaf_lights);
  std::vector<gpu::LightRange> r(clusters);
  std::vector<std::uint32_t> rec(2 * (total + 8)), leaf(slots + 16);
  if (clusters) q.enqueueReadBuffer(ranges, CL_TRUE, 0, clusters * 8, r.data());
  q.enqueueReadBuffer(records, CL_TRUE, 0, rec.size() * 4, rec.data());
  q.enqueueReadBuffer(leaf_lights, CL_TRUE, 0, leaf.size() * 4, leaf.data());
  for (std::size_t i = 2 * std::size_t(total); i < rec.size(); ++i) EXPECT_EQ(rec[i], kPoison) << "write past the list end";
  for (std::size_t i = slots; i < leaf.size(); ++i) EXPECT_EQ(leaf[i], kPoison) << "write past the leaf slots";
  if (raw) *raw = {r, {rec.begin(), rec.begin() + 2 * std::ptrdiff_t(total)}, {leaf.begin(), leaf.begin() + std::ptrdiff_t(slots)}};
  // Brute force: every light sits in exactly one slot. BVH: only the lights
  // that reach the box around all clusters, each in one slot (that none is
  // missing shows as lists unequal to brute force's). Slots past the last
  // light are empty.
  std::vector<std::uint32_t> seen(n, 0);
  for (std::size_t i = 0; i < slots; ++i) {
    if (leaf[i] == 0xffffffffu) continue;
    if (leaf[i] >= n) {
      ADD_FAILURE() << "leaf slot " << i << " holds " << leaf[i];
      continue;
    }
    ++seen[leaf[i]];
  }
  if (clusters && a.method() == ClusterAssignMethod::Brute) {
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1u), std::ptrdiff_t(n)) << "leaf slots are not a permutation";
  }
  EXPECT_EQ(std::count_if(seen.begin(), seen.end(), [](std::uint32_t v) { return v > 1; }), 0) << "a light in two slots";
  std::vector<std::vector<std::uint32_t>> lists(clusters);
  std::uint32_t offset = 0;
  std::uint64_t lights_listed = 0;
  for (std::uint32_t k = 0; k < clusters; ++k) {
    EXPECT_EQ(r[k].offset, offset) << "cluster " << k;
    offset += r[k].count;
    if (r[k].offset + r[k].count > total) {
      ADD_FAILURE() << "cluster " << k << " out of range";
      continue;
    }
    for (std::uint32_t j = r[k].offset; j < r[k].offset + r[k].count; ++j) {
      const std::uint32_t slot = rec[2 * j], mask = rec[2 * j + 1];
      if (mask == 0 || slot % a.leafSize() != 0 || slot + a.leafSize() > slots) {
        ADD_FAILURE() << "cluster " << k << ": bad record (" << slot << ", " << mask << ")";
        continue;
      }
      for (unsigned b = 0; b < a.leafSize(); ++b) {
        if (!(mask >> b & 1u)) continue;
        EXPECT_LT(leaf[slot + b], n) << "cluster " << k << " lists an empty slot";
        lists[k].push_back(leaf[slot + b]);
      }
    }
    lights_listed += lists[k].size();
    std::sort(lists[k].begin(), lists[k].end());
    EXPECT_EQ(std::adjacent_find(lists[k].begin(), lists[k].end()), lists[k].end()) << "cluster " << k << ": a light twice";
  }
  EXPECT_EQ(offset, total);
  EXPECT_EQ(a.hitLeaves(q), total);
  EXPECT_EQ(a.listedLights(q), lights_listed);
  return lists;
}

// The device's explicit boxes, read back after a count().
std::vector<ClusterBox> deviceBoxes(ClusterLightAssigner& a, std::size_t clusters) {
  std::vector<cl_float4> lo(clusters), hi(clusters);
  auto& q = test::runtime().queue();
  if (clusters) {
    q.enqueueReadBuffer(a.boxLo(), CL_TRUE, 0, clusters * 16, lo.data());
    q.enqueueReadBuffer(a.boxHi(), CL_TRUE, 0, clusters * 16, hi.data());
  }
  std::vector<ClusterBox> out;
  for (std::size_t k = 0; k < clusters; ++k)
    out.push_back({lo[k].s[0], hi[k].s[0], lo[k].s[1], hi[k].s[1], lo[k].s[2], hi[k].s[2]});
  return out;
}

void poisonBoxes(ClusterLightAssigner& a, std::size_t clusters) {
  auto& q = test::runtime().queue();
  const cl_float4 nan{{std::numeric_limits<float>::quiet_NaN(), 1.0f, -1.0f, 0.0f}};
  if (clusters) {
    q.enqueueFillBuffer(a.boxLo(), nan, 0, clusters * 16);
    q.enqueueFillBuffer(a.boxHi(), nan, 0, clusters * 16);
  }
}

// The device's explicit boxes bit for bit against the C++ reduction: the
// reduction is min/max only and the per-pixel math has no contraction
// (within the stated tolerance where division and sqrt are not correctly rounded).
void expectDeviceBoxesMatch(ClusterLightAssigner& a, const std::vector<ClusterBox>& ref_boxes) {
  const auto got = deviceBoxes(a, ref_boxes.size());
  const auto eq = [](float x, float y) { return test::floatsMatch(x, y); };
  for (std::size_t k = 0; k < got.size(); ++k) {
    const ClusterBox& e = ref_boxes[k];
    const ClusterBox& g = got[k];
    ASSERT_TRUE(eq(g.x0, e.x0) && eq(g.x1, e.x1) && eq(g.y0, e.y0) && eq(g.y1, e.y1) && eq(g.z0, e.z0) &&
                eq(g.z1, e.z1))
        << "cluster " << k << ": got x " << g.x0 << ".." << g.x1 << " y " << g.y0 << ".." << g.y1 << " z " << g.z0
        << ".." << g.z1 << ", expected x " << e.x0 << ".." << e.x1 << " y " << e.y0 << ".." << e.y1 << " z " << e.z0
        << ".." << e.z1;
  }
}

// Conservative: a light containing a pixel's surface point is in its cluster's list.
void expectConservative(const test::ClusterCase& c, const Frame& f, const std::vector<std::vector<std::uint32_t>>& lists,
                        unsigned w, unsigned h) {
  const gpu::CameraParams cam = c.camera.params(w, h);
  for (unsigned y = 0; y < h; y += 3)
    for (unsigned x = 0; x < w; x += 3) {
      const std::size_t p = std::size_t(y) * w + x;
      if (gpu::is_sky_depth(c.depth[p])) continue;
      const glm::dvec3 wp = test::pixelWorldPoint(c.camera, cam, x, y, c.depth[p]);
      const auto& list = lists[f.cluster_of[p]];
      for (std::uint32_t i = 0; i < c.lights.size(); ++i) {
        const auto& l = c.lights[i].position_radius;
        const glm::dvec3 d = wp - glm::dvec3(l.x, l.y, l.z);
        if (glm::dot(d, d) < double(l.w) * l.w * 0.999) {
          ASSERT_TRUE(std::binary_search(list.begin(), list.end(), i)) << "pixel " << x << "," << y << " light " << i;
        }
      }
    }
}

std::size_t pairCount(const std::vector<std::vector<std::uint32_t>>& lists) {
  std::size_t pairs = 0;
  for (const auto& l : lists) pairs += l.size();
  return pairs;
}

// Every assigner configuration the brute-vs-BVH test compares with the reference.
struct AssignerSet {
  AssignerSet(ClRuntime& rt, KernelShape shape)
      : brute(rt, ClusterAssignMethod::Brute, 32, shape),
        bvh(rt, ClusterAssignMethod::Bvh, 32, shape),
        brute_rewalk(rt, ClusterAssignMethod::Brute, 32, shape),
        bvh_rewalk(rt, ClusterAssignMethod::Bvh, 32, shape),
        bvh8(rt, ClusterAssignMethod::Bvh, 8, shape),
        bvh16(rt, ClusterAssignMethod::Bvh, 16, shape),
        brute8(rt, ClusterAssignMethod::Brute, 8, shape),
        bvh_key_order(rt, ClusterAssignMethod::Bvh, 32, shape) {
    // One hit-leaf record per cluster: the fill pass walks again for most clusters.
    brute_rewalk.setRecordBudget(1);
    bvh_rewalk.setRecordBudget(1);
    // The BVH passes in key order instead of tile-Morton order.
    bvh_key_order.setClusterOrder(false);
  }
  ClusterLightAssigner brute, bvh;
  ClusterLightAssigner brute_rewalk, bvh_rewalk;
  // Smaller leaves: other tree shapes over the same lights (leaf 8 walks one
  // more level at 40000 lights), and brute force over them.
  ClusterLightAssigner bvh8, bvh16, brute8;
  ClusterLightAssigner bvh_key_order;
};

// The other configurations against the reference (exact where division and
// sqrt round correctly, else the stated tolerance); the walk-again path only
// with the explicit bounds (the default). Returns the BVH's lists.
std::vector<std::vector<std::uint32_t>> expectVariantsMatch(AssignerSet& s, ClusterUniquer& u, const test::ClusterCase& c,
                                                            const Frame& f, const ClusterPixels* pixels,
                                                            const std::vector<std::vector<std::uint32_t>>& ref) {
  const auto t = assign(s.bvh, u, c, f, pixels);
  EXPECT_TRUE(test::listsMatch(t, ref, "bvh, cluster"));
  if (pixels) {
    EXPECT_TRUE(test::listsMatch(assign(s.brute_rewalk, u, c, f, pixels), ref, "brute walking again, cluster"));
    EXPECT_TRUE(test::listsMatch(assign(s.bvh_rewalk, u, c, f, pixels), ref, "bvh walking again, cluster"));
  }
  EXPECT_TRUE(test::listsMatch(assign(s.bvh8, u, c, f, pixels), ref, "bvh, leaf 8, cluster"));
  EXPECT_TRUE(test::listsMatch(assign(s.bvh16, u, c, f, pixels), ref, "bvh, leaf 16, cluster"));
  EXPECT_TRUE(test::listsMatch(assign(s.brute8, u, c, f, pixels), ref, "brute, leaf 8, cluster"));
  EXPECT_TRUE(test::listsMatch(assign(s.bvh_key_order, u, c, f, pixels), ref, "bvh in key order, cluster"));
  return t;
}

class ClusteredAssign : public ::testing::TestWithParam<KernelShape> {};

TEST(ClusteredAssignLeaves, RejectsUnsupportedLeafSizes) {
  for (unsigned leaf : {0u, 1u, 4u, 24u, 64u})
    EXPECT_THROW(ClusterLightAssigner(test::runtime(), ClusterAssignMethod::Bvh, leaf), UserError) << leaf;
}

// Levels of a BVH of branching 32 over `lights` (0 without lights).
unsigned expectedLevels(std::uint32_t lights, unsigned leaf_size) {
  if (lights == 0) return 0;
  unsigned levels = 1;
  for (std::uint32_t c = (lights + leaf_size - 1) / leaf_size; c > 32; c = (c + 31) / 32) ++levels;
  return levels;
}

TEST_P(ClusteredAssign, BruteMatchesReferenceAndBvhMatchesBrute) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClRuntime& rt = test::runtime();
  const KernelShape shape = GetParam();
  ClusterUniquer u(rt, UniqueMethod::PageTable, 6, shape);
  AssignerSet s(rt, shape);
  EXPECT_EQ(s.bvh.shape(), shape);
  // Light counts give BVHs of 1 (< 32 lights), 2 and (usually) 3 levels, and none at all.
  using Case = std::tuple<unsigned, unsigned, unsigned, unsigned>;
  const std::vector<Case> cases =
      test::smallTests() ? std::vector<Case>{{48u, 32u, 16u, 20u}, {40u, 24u, 8u, 1100u}, {20u, 12u, 8u, 0u}}
                         : std::vector<Case>{{160u, 96u, 32u, 20u}, {203u, 117u, 16u, 3000u}, {64u, 48u, 32u, 48000u},
                                             {50u, 30u, 8u, 0u}};
  for (auto [w, h, tile, n] : cases) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(tile) + " lights " +
                 std::to_string(n));
    const auto c = test::randomClusterCase(rng, w, h, n);
    cl::Buffer depth(rt.context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
    const Frame f = clusters(u, c, depth, tile);
    ASSERT_GT(f.unique.size(), 0u);
    const ClusterPixels pixels{depth, u.clusterOf()};
    std::size_t frustum_pairs = 0;
    for (ClusterBounds bounds : {ClusterBounds::Frustum, ClusterBounds::Pixels}) {
      SCOPED_TRACE(clusterBoundsName(bounds));
      const bool explicit_bounds = bounds == ClusterBounds::Pixels;
      const ClusterPixels* px = explicit_bounds ? &pixels : nullptr;
      const auto ref_boxes = explicit_bounds ? pixelBoxes(c.depth.data(), f.cluster_of, std::uint32_t(f.unique.size()), c.cam())
                                             : std::vector<ClusterBox>{};
      const auto ref = explicit_bounds ? referenceAssign(ref_boxes, c.lights, c.cam())
                                       : referenceAssign(f.unique, c.lights, c.cam(), f.grid);
      if (explicit_bounds) {
        // Sizes the box buffers; then poison them so that a box the kernel misses shows.
        assign(s.brute, u, c, f, px);
        poisonBoxes(s.brute, f.unique.size());
      }
      ASSERT_TRUE(test::listsMatch(assign(s.brute, u, c, f, px), ref, "brute, cluster"));
      if (explicit_bounds) expectDeviceBoxesMatch(s.brute, ref_boxes);
      const auto t = expectVariantsMatch(s, u, c, f, px, ref);
      ASSERT_FALSE(HasFailure());
      const std::size_t pairs = pairCount(ref);
      // (20 lights may all miss the tight boxes of the pixels.)
      if (n > 0 && (n >= 1000 || !explicit_bounds)) {
        EXPECT_GT(pairs, 0u);
      }
      // Explicit bounds tighten the lists overall (a box may reach past its
      // slice by its padding, so not cluster by cluster).
      if (explicit_bounds) {
        EXPECT_LE(pairs, frustum_pairs);
      }
      frustum_pairs = pairs;
      // The BVH holds the lights that reach the clusters' union box: at 48,000
      // lights (most of them in reach) usually 3 levels, at least 2.
      EXPECT_LE(s.bvh.treeLights(), n);
      EXPECT_EQ(s.bvh.bvhLevels(), expectedLevels(s.bvh.treeLights(), s.bvh.leafSize()));
      EXPECT_EQ(s.bvh8.bvhLevels(), expectedLevels(s.bvh8.treeLights(), s.bvh8.leafSize()));
      if (n == 48000) {
        EXPECT_GE(s.bvh.bvhLevels(), 2u);
      }
      expectConservative(c, f, t, w, h);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ClusteredAssign, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

// The GPU shape against the CPU shape: the same boxes bit for bit, the same
// ranges, records (in the same order) and leaf slots, for both methods and
// both bounds, with and without the fill pass walking again.
TEST(ClusteredAssignShapes, GpuShapeEqualsCpuShapeExactly) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClRuntime& rt = test::runtime();
  ClusterUniquer u(rt, UniqueMethod::PageTable, 6, KernelShape::CpuChunked);
  const bool small = test::smallTests();
  const auto c = test::randomClusterCase(rng, small ? 40 : 203, small ? 24 : 117, small ? 1100 : 5000);
  cl::Buffer depth(rt.context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
  const Frame f = clusters(u, c, depth, 8);
  const ClusterPixels pixels{depth, u.clusterOf()};
  for (ClusterAssignMethod m : {ClusterAssignMethod::Bvh, ClusterAssignMethod::Brute})
    for (ClusterBounds bounds : {ClusterBounds::Frustum, ClusterBounds::Pixels})
      for (std::size_t budget : {std::size_t(1) << 22, std::size_t(1)}) {
        SCOPED_TRACE(std::string(clusterAssignName(m)) + " " + clusterBoundsName(bounds) + " budget " +
                     std::to_string(budget));
        RawLists raw[2];
        std::vector<ClusterBox> boxes[2];
        for (int s = 0; s < 2; ++s) {
          ClusterLightAssigner a(rt, m, 32, test::kBothShapes[s]);
          a.setRecordBudget(budget);
          assign(a, u, c, f, bounds == ClusterBounds::Pixels ? &pixels : nullptr, &raw[s]);
          boxes[s] = deviceBoxes(a, f.unique.size());
        }
        for (std::size_t k = 0; k < boxes[0].size(); ++k) {
          const ClusterBox& a = boxes[0][k];
          const ClusterBox& b = boxes[1][k];
          ASSERT_TRUE(a.x0 == b.x0 && a.x1 == b.x1 && a.y0 == b.y0 && a.y1 == b.y1 && a.z0 == b.z0 && a.z1 == b.z1)
              << "cluster " << k;
        }
        ASSERT_EQ(raw[0].ranges.size(), raw[1].ranges.size());
        for (std::size_t k = 0; k < raw[0].ranges.size(); ++k) {
          ASSERT_EQ(raw[0].ranges[k].offset, raw[1].ranges[k].offset) << "cluster " << k;
          ASSERT_EQ(raw[0].ranges[k].count, raw[1].ranges[k].count) << "cluster " << k;
        }
        EXPECT_EQ(raw[0].records, raw[1].records);
        EXPECT_EQ(raw[0].leaf_lights, raw[1].leaf_lights);
        EXPECT_GT(raw[0].records.size(), 0u);
      }
}

// The GPU shape with every group (its own kernels' and the primitives') held
// to 32, 64, 256 items and the device maximum: the same clusters (sort-based
// uniquing: the radix, segmented sorts, scan and compaction) and the same
// boxes, ranges, records and leaf slots as the CPU shape. A kernel that
// depends on one group size differs at some other.
TEST(ClusteredAssignShapes, GpuShapeAtForcedGroupSizesEqualsCpuShape) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  ClRuntime& rt = test::runtime();
  const bool small = test::smallTests();
  const auto c = test::randomClusterCase(rng, small ? 40 : 160, small ? 24 : 96, small ? 1100 : 5000);
  cl::Buffer depth(rt.context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
  ClusterUniquer cpu_u(rt, UniqueMethod::TileSort, 6, KernelShape::CpuChunked);
  const Frame want = clusters(cpu_u, c, depth, 8);
  const ClusterPixels cpu_pixels{depth, cpu_u.clusterOf()};
  ClusterLightAssigner cpu_a(rt, ClusterAssignMethod::Bvh, 32, KernelShape::CpuChunked);
  RawLists cpu_raw;
  assign(cpu_a, cpu_u, c, want, &cpu_pixels, &cpu_raw);
  const auto cpu_boxes = deviceBoxes(cpu_a, want.unique.size());
  std::size_t device_max = 1;
  while (device_max * 2 <= rt.info().max_work_group_size) device_max *= 2;
  for (const std::size_t group : {std::size_t(32), std::size_t(64), std::size_t(256), device_max}) {
    SCOPED_TRACE("max_group=" + std::to_string(group));
    for (const UniqueMethod m : {UniqueMethod::TileSort, UniqueMethod::Sort}) {
      ClusterUniquer u(rt, m, 6, KernelShape::GpuWorkGroup, group);
      const Frame f = clusters(u, c, depth, 8);
      ASSERT_EQ(f.unique, want.unique) << uniqueMethodName(m);
      ASSERT_EQ(f.cluster_of, want.cluster_of) << uniqueMethodName(m);
    }
    ClusterLightAssigner a(rt, ClusterAssignMethod::Bvh, 32, KernelShape::GpuWorkGroup, group);
    RawLists raw;
    assign(a, cpu_u, c, want, &cpu_pixels, &raw);
    const auto boxes = deviceBoxes(a, want.unique.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const ClusterBox& x = boxes[k];
      const ClusterBox& y = cpu_boxes[k];
      ASSERT_TRUE(x.x0 == y.x0 && x.x1 == y.x1 && x.y0 == y.y0 && x.y1 == y.y1 && x.z0 == y.z0 && x.z1 == y.z1)
          << "cluster " << k;
    }
    ASSERT_EQ(raw.ranges.size(), cpu_raw.ranges.size());
    for (std::size_t k = 0; k < raw.ranges.size(); ++k) {
      ASSERT_EQ(raw.ranges[k].offset, cpu_raw.ranges[k].offset) << "cluster " << k;
      ASSERT_EQ(raw.ranges[k].count, cpu_raw.ranges[k].count) << "cluster " << k;
    }
    EXPECT_EQ(raw.records, cpu_raw.records);
    EXPECT_EQ(raw.leaf_lights, cpu_raw.leaf_lights);
  }
  EXPECT_GT(cpu_raw.records.size(), 0u);
  EXPECT_THROW(ClusterLightAssigner(rt, ClusterAssignMethod::Bvh, 32, KernelShape::GpuWorkGroup, 16), UserError);
}

}  // namespace
}  // namespace ml
