// Voxel injection's hashed lists under light changes (vct::HashedListsCl fed
// incrementally through hashed::GpuUploadPlan, and vct::VctPipeline), both
// kernel shapes:
//  - after every update of a random edit sequence (moves, additions,
//    removals; one batch of additions quadrupling the lights, which must resize a hash
//    table, one move out of the octree that must rebuild), the OpenCL
//    buffers read back equal the structure's whole image word for word (a
//    partial upload leaves no stale word), the OpenCL lookup returns the host
//    lookup's range at random points, the host lookup's lights equal a fresh
//    build's on the same lights and bounds, and injection through the
//    buffers equals the brute-force twin (vct_inject_test.cpp's tolerance);
//    updates that neither rebuilt nor resized upload less than the image;
//  - a pipeline whose later updates move a few lights takes the incremental
//    path (counted), uploads less than the image at least once, and its
//    volume equals that of a pipeline built fresh on the moved lights.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "gl/SceneGpu.hpp"
#include "host/compute/HostIo.hpp"
#include "host/hashed/HashedStructure.hpp"
#include "host/vct/HashedListsCl.hpp"
#include "host/vct/VctPipeline.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "support/shape_support.hpp"
#include "support/RandomSoup.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"
#include "vct_inject_support.hpp"

namespace ml::vct {
namespace {

using namespace inject_case;

// The lights' spheres' box: moving a light toward its centre, or adding a
// smaller light inside another's sphere, keeps every light in the octree.
struct SphereBox {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  explicit SphereBox(const std::vector<gpu::PointLight>& lights) {
    for (const auto& l : lights) {
      const glm::vec3 p(l.position_radius.x, l.position_radius.y, l.position_radius.z);
      lo = glm::min(lo, p - l.position_radius.w);
      hi = glm::max(hi, p + l.position_radius.w);
    }
  }
  glm::vec3 centre() const { return (lo + hi) * 0.5f; }
};

void moveToward(gpu::PointLight& l, const glm::vec3& target, float t) {
  l.position_radius.x += (target.x - l.position_radius.x) * t;
  l.position_radius.y += (target.y - l.position_radius.y) * t;
  l.position_radius.z += (target.z - l.position_radius.z) * t;
}

// A light inside `host`'s sphere, a quarter of its radius or less.
gpu::PointLight insideOf(const gpu::PointLight& host, std::mt19937_64& rng) {
  gpu::PointLight l = host;
  const float r = host.position_radius.w;
  l.position_radius.x += uni(rng, -0.5f, 0.5f) * r;
  l.position_radius.y += uni(rng, -0.5f, 0.5f) * r;
  l.position_radius.z += uni(rng, -0.5f, 0.5f) * r;
  l.position_radius.w = r * uni(rng, 0.02f, 0.25f);
  return l;
}

// A light whose sphere lies in the box.
gpu::PointLight inBox(const SphereBox& box, float r, std::mt19937_64& rng) {
  const glm::vec3 lo = box.lo + r, hi = glm::max(box.hi - r, lo);
  return makeLight({uni(rng, lo.x, hi.x), uni(rng, lo.y, hi.y), uni(rng, lo.z, hi.z)}, r,
                   glm::vec3(uni(rng, 0, 1), uni(rng, 0, 1), uni(rng, 0, 1)));
}

// Lights in [0, 10]^3, radii 0.2-1: room between them for new cells.
std::vector<gpu::PointLight> sparseLights(std::size_t n, std::mt19937_64& rng) {
  SphereBox box(std::vector<gpu::PointLight>{});
  box.lo = glm::vec3(0.0f);
  box.hi = glm::vec3(10.0f);
  std::vector<gpu::PointLight> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(inBox(box, uni(rng, 0.2f, 1.0f), rng));
  return out;
}

enum class Batch { Small, Cluster, Leave };

// Small: ~5% of the lights move toward the centre, 1-3 added, 1-3 removed.
// Cluster: three times as many small lights added as there are, anywhere in
// the box (new cells: a table must grow). Leave: one light far outside.
void edit(std::vector<gpu::PointLight>& lights, Batch batch, std::mt19937_64& rng) {
  const SphereBox box(lights);
  if (batch == Batch::Leave) {
    lights[rng() % lights.size()].position_radius.x = box.hi.x + 3.0f * (box.hi.x - box.lo.x);
    return;
  }
  const std::size_t n = lights.size();
  if (batch == Batch::Cluster) {
    for (std::size_t i = 0; i < 3 * n; ++i) lights.push_back(inBox(box, uni(rng, 0.1f, 0.4f), rng));
    return;
  }
  for (std::size_t i = 0; i < std::max<std::size_t>(1, n / 20); ++i)
    moveToward(lights[rng() % lights.size()], box.centre(), uni(rng, 0.05f, 0.4f));
  for (std::size_t i = 1 + rng() % 3; i > 0; --i) lights.push_back(insideOf(lights[rng() % lights.size()], rng));
  for (std::size_t i = 1 + rng() % 3; i > 0 && lights.size() > 2; --i) {
    const std::size_t victim = rng() % lights.size();
    lights[victim] = lights.back();
    lights.pop_back();
  }
}

class VctListsUpdate : public ::testing::TestWithParam<KernelShape> {
 protected:
  // The OpenCL copy against the host structure and a fresh build.
  void checkCopy(const hashed::HashedStructure& hs, std::mt19937_64& rng) {
    auto& q = test::runtime().queue();
    ASSERT_EQ(lists_.staleArray(q, hs.linkless()), "") << "stale words in the OpenCL copy";
    hashed::HashedStructure fresh(hs.config());
    fresh.build(hs.lights(), hs.bounds());
    const auto& b = hs.linkless().bounds();
    const glm::vec3 lo = b.origin_f, hi = lo + glm::vec3(float(1u << b.depth) / b.cell_scale);
    std::vector<F4> points;
    for (int i = 0; i < (test::smallTests() ? 500 : 3000); ++i) {
      const glm::vec3 p = lo + glm::vec3(uni(rng, -0.05f, 1.05f), uni(rng, -0.05f, 1.05f), uni(rng, -0.05f, 1.05f)) *
                                   (hi - lo);
      points.push_back({p.x, p.y, p.z, 0});
    }
    const auto got = lists_.lookup(q, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::vec3 p(points[i].x, points[i].y, points[i].z);
      const auto want = hs.linkless().lookup(p);
      ASSERT_EQ(got[i].offset, want.offset) << "point " << i;
      ASSERT_EQ(got[i].count, want.count) << "point " << i;
      if (want.count) {
        ASSERT_EQ(got[i].octant, want.octant) << "point " << i;
      }
      ASSERT_EQ(hs.linkless().lightsAt(p), fresh.linkless().lightsAt(p)) << "point " << i << ": not a fresh build's";
    }
  }

  // Injection through the OpenCL copy against the brute-force twin.
  void checkInjection(const std::vector<gpu::PointLight>& lights, std::mt19937_64& rng) {
    auto& rt = test::runtime();
    auto& q = rt.queue();
    const unsigned edge = test::smallTests() ? 8 : 16;
    gpu::VoxelGridParams g = randomGrid(edge, rng);
    const SphereBox box(lights);  // the grid over the lights, so that most voxels see some
    const float size = std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z});
    g.origin_voxel_size = {box.lo.x, box.lo.y, box.lo.z, size / float(edge)};
    const auto accum = randomAccum(edge, rng);
    cl::Buffer ab = compute::upload(rt.context(), q, accum), lb = compute::upload(rt.context(), q, lights);
    cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, accum.size() * 16);
    compute::poison(q, out);
    injector_.hashed(q, g, ab, lb, lights.size(), lists_, out);
    const auto want = injectTwin(accum, g, lights);
    EXPECT_EQ(compare(compute::download<F4>(q, out, want.size()), want, toleranceScale(accum, g, lights), false), "");
  }

  compute::ComputeEnv env_{test::runtime()};
  VoxelInjector injector_{env_, compute::Options{.shape = GetParam()}};
  HashedListsCl lists_{env_};
};

TEST_P(VctListsUpdate, RandomEditsKeepTheOpenClCopyExact) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  auto lights = sparseLights(test::smallTests() ? 60 : 300, rng);
  hashed::HashedConfig cfg;
  cfg.max_incremental_fraction = 1.0;  // the cluster batch quadruples the lights: still an update
  hashed::HashedStructure hs(cfg);
  auto& q = test::runtime().queue();
  const Batch plan[] = {Batch::Small, Batch::Small, Batch::Cluster, Batch::Small, Batch::Small,
                        Batch::Leave, Batch::Small, Batch::Small, Batch::Small};
  std::size_t partial = 0, resized = 0, rebuilt = 0;
  for (int round = -1; round < int(std::size(plan)); ++round) {
    SCOPED_TRACE("round " + std::to_string(round) + ", " + std::to_string(lights.size()) + " lights");
    if (round >= 0) edit(lights, plan[round], rng);
    const std::uint64_t layout = hs.built() ? hs.linkless().layoutVersion() : ~0ull;
    const hashed::UpdateStats& st = hs.update(lights);
    const bool resize = !st.full_rebuild && hs.linkless().layoutVersion() != layout;
    lists_.upload(q, hs.linkless(), st.full_rebuild);
    EXPECT_EQ(lists_.lastUploadWasFull(), st.full_rebuild || resize);
    if (round >= 0) {
      EXPECT_EQ(st.full_rebuild, plan[round] == Batch::Leave) << st.reason;
    }
    EXPECT_TRUE(lists_.lastUploadWasFull() || lists_.lastUploadBytes() < hs.linkless().gpuBytes())
        << "a partial upload as large as the image";
    partial += !lists_.lastUploadWasFull();
    resized += resize;
    rebuilt += st.full_rebuild;
    checkCopy(hs, rng);
    checkInjection(lights, rng);
    if (HasFailure()) return;
  }
  // Both upload kinds ran: the first update after a build nearly always
  // resizes a table (the build sizes them tight), as the cluster batch
  // mostly does; the other small batches mostly fit.
  EXPECT_GE(partial, 2u);
  EXPECT_GE(resized, 1u);
  EXPECT_EQ(rebuilt, 2u);  // the first build and the light that left
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctListsUpdate, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

// The volume as one float4 per voxel of every level.
std::vector<F4> radianceOf(VctPipeline& p) {
  SharedBuffer& b = p.volume().radiance();
  std::vector<F4> out(b.size() / sizeof(F4));
  b.download(out.data(), out.size() * sizeof(F4));
  return out;
}

class VctPipelineLists : public ::testing::TestWithParam<KernelShape> {};

TEST_P(VctPipelineLists, FewMovedLightsUpdateAndEqualAFreshPipeline) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = test::randomSoup(rng, 30);
  SceneGpu gpu_scene(scene);
  VctPipelineOptions o;
  o.grid = {16, 3, true};
  o.compute.shape = GetParam();
  auto lights = test::randomLightsIn(rng, 64, scene.bounds);
  for (auto& l : lights) l.position_radius.w *= 0.3f;  // some lights miss some voxels
  VctPipeline p(test::runtime(), o, scene.bounds);
  PassTimings t;
  p.update(gpu_scene, lights, t);
  // Three updates: the first after the build usually resizes a table (the
  // build sizes them tight) and uploads everything; later ones fit.
  std::size_t partial = 0;
  for (int update = 0; update < 3; ++update) {
    const SphereBox box(lights);
    for (int i = 0; i < 4; ++i) moveToward(lights[rng() % lights.size()], box.centre(), uni(rng, 0.1f, 0.5f));
    p.update(gpu_scene, lights, t);
    partial += p.lastListUploadBytes() < p.lists().linkless().gpuBytes();
  }
  EXPECT_EQ(p.listBuilds(), 1u);
  EXPECT_EQ(p.listUpdates(), 3u) << p.lists().lastUpdate().reason;
  EXPECT_GE(partial, 1u) << "every update uploaded everything";
  VctPipeline fresh(test::runtime(), o, scene.bounds);
  fresh.update(gpu_scene, lights, t);
  EXPECT_EQ(fresh.listBuilds(), 1u);
  const auto got = radianceOf(p), want = radianceOf(fresh);
  ASSERT_EQ(got.size(), want.size());
  bool lit = false;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const float g[4] = {got[i].x, got[i].y, got[i].z, got[i].w}, w[4] = {want[i].x, want[i].y, want[i].z, want[i].w};
    for (int c = 0; c < 4; ++c) ASSERT_NEAR(g[c], w[c], 1e-5f * std::fabs(w[c]) + 1e-7f) << "voxel " << i << "." << c;
    lit |= w[0] > 0;
  }
  EXPECT_TRUE(lit) << "no voxel lit: the comparison would prove nothing";
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctPipelineLists, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml::vct
