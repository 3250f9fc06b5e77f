// Voxel light injection (kernels/vct/vct_inject.cl through vct::VoxelInjector),
// both kernel shapes:
//  - brute force equals the C++ twin (host/vct/InjectTwin.hpp) on random
//    accumulation volumes and random lights: 0 and 1 light, lights outside
//    the grid, radii spanning the whole grid, voxels whose normals cancel.
//  - through the hashed structure's lists equals brute force: only the
//    summation order differs.
//  - the OpenCL port of the hashed lookup returns LinklessOctree::lookup()'s
//    range and octant for random points in and around the octree.
//  - a known value pins the shading model itself.
//  - with voxel shadows (VCT_SHADOWS, InjectTwin's shadows = true): brute
//    force and hashed equal the twin on sparse random volumes (shadowed and
//    lit terms both occur, checked), and a closed wall between a light and
//    the far side zeroes the far side's light and leaves the near side's
//    bit for bit. The visibility is a discrete decision, so the twin is
//    compared bit-exactly only where the device divides correctly (as
//    above); elsewhere a sample landing on a voxel face may flip it.
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
#include "support/shape_support.hpp"
#include "vct_inject_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"

namespace ml::vct {
namespace {

using namespace inject_case;

struct Case {
  std::vector<gpu::VoxelAccum> accum;
  gpu::VoxelGridParams grid;
  std::vector<gpu::PointLight> lights;
};

class VctInject : public ::testing::TestWithParam<KernelShape> {
 protected:
  // Brute force and hashed on the device for `c`, each against the twin.
  // Returns the brute-force output.
  std::vector<F4> check(const Case& c, bool shadows = false) {
    auto& rt = test::runtime();
    auto& q = rt.queue();
    VoxelInjector& injector = shadows ? shadowed_ : injector_;
    const auto want = injectTwin(c.accum, c.grid, c.lights, shadows);
    const auto scale = toleranceScale(c.accum, c.grid, c.lights);
    cl::Buffer accum = compute::upload(rt.context(), q, c.accum);
    cl::Buffer lights = compute::upload(rt.context(), q, c.lights);
    cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, want.size() * 16);
    compute::poison(q, out);
    injector.brute(q, c.grid, accum, lights, c.lights.size(), out);
    const auto brute = compute::download<F4>(q, out, want.size());
    EXPECT_EQ(compare(brute, want, scale, test::exactDivideSqrt()), "") << "brute force, shadows " << shadows;
    if (c.lights.empty()) return brute;  // the hashed structure needs lights to bound
    hashed::HashedStructure hs(hashed::HashedConfig{});
    hs.build(c.lights);
    lists_.upload(q, hs.linkless(), true);
    compute::poison(q, out);
    injector.hashed(q, c.grid, accum, lights, c.lights.size(), lists_, out);
    EXPECT_EQ(compare(compute::download<F4>(q, out, want.size()), want, scale, false), "")
        << "hashed lists, shadows " << shadows;
    return brute;
  }
  compute::ComputeEnv env_{test::runtime()};
  VoxelInjector injector_{env_, compute::Options{.shape = GetParam()}};
  VoxelInjector shadowed_{env_, compute::Options{.shape = GetParam()}, true};
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

// Sparse volumes (1 in 12 voxels filled) so that some lights are hidden and
// some seen; over the whole test both must occur, else it proves little.
TEST_P(VctInject, VoxelShadowsMatchTwinOnRandomVolumes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const unsigned largest = test::smallTests() ? 8 : 32;
  std::size_t dimmed = 0, kept = 0;
  for (unsigned edge = 1; edge <= largest; edge *= 2)
    for (std::size_t lights : {0, 1, 2, 7, 100}) {
      SCOPED_TRACE("edge=" + std::to_string(edge) + " lights=" + std::to_string(lights));
      Case c{randomAccum(edge, rng, 12), randomGrid(edge, rng), {}};
      c.lights = randomLights(lights, c.grid, rng);
      check(c, true);
      const auto lit = injectTwin(c.accum, c.grid, c.lights), shadowed = injectTwin(c.accum, c.grid, c.lights, true);
      for (std::size_t i = 0; i < lit.size(); ++i) {
        const float a = lit[i].x + lit[i].y + lit[i].z, b = shadowed[i].x + shadowed[i].y + shadowed[i].z;
        dimmed += b < a;
        kept += b > 0 && b == a;
      }
    }
  EXPECT_GT(dimmed, 0u) << "no voxel lost light to a shadow";
  EXPECT_GT(kept, 0u) << "no lit voxel kept all its light";
}

// A closed wall (every voxel of the plane x = 4 of an 8^3 grid, facing -x)
// with a light at x = 2.5: receivers at x = 6 facing the light get nothing,
// those at x = 0 facing it and the wall itself keep their unshadowed light
// exactly, through brute force and the hashed lists.
TEST_P(VctInject, ClosedWallHidesTheFarSideOnly) {
  Case c{std::vector<gpu::VoxelAccum>(512, gpu::VoxelAccum{}), gpu::VoxelGridParams{}, {}};
  c.grid.origin_voxel_size = {0, 0, 0, 1};
  c.grid.edge = 8;
  c.grid.levels = 1;
  const auto fill = [&](unsigned x, unsigned y, unsigned z, int nx) {
    auto& v = c.accum[(z * 8 + y) * 8 + x];
    v.albedo_count[0] = v.albedo_count[1] = v.albedo_count[2] = 200;
    v.albedo_count[3] = 1;
    v.normal_sum[0] = nx * 1024;
  };
  for (unsigned y = 0; y < 8; ++y)
    for (unsigned z = 0; z < 8; ++z) fill(4, y, z, -1);
  for (unsigned y = 1; y < 7; ++y)
    for (unsigned z = 1; z < 7; ++z) fill(0, y, z, 1), fill(6, y, z, -1);
  c.lights = {makeLight({2.5f, 4.0f, 4.0f}, 30.0f, {1.0f, 0.8f, 0.6f})};
  const auto lit = check(c, false), shadowed = check(c, true);
  for (unsigned i = 0; i < 512; ++i) {
    const unsigned x = i % 8;
    if (c.accum[i].albedo_count[3] == 0) continue;
    SCOPED_TRACE("voxel " + std::to_string(i));
    ASSERT_GT(lit[i].x, 0.0f) << "the unshadowed light must reach every receiver";
    if (x == 6) {
      EXPECT_EQ(shadowed[i].x + shadowed[i].y + shadowed[i].z, 0.0f) << "light through the wall";
      EXPECT_EQ(shadowed[i].w, 1.0f);
    } else {
      EXPECT_EQ(std::memcmp(&shadowed[i], &lit[i], sizeof(F4)), 0) << "the near side changed";
    }
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
  lists_.upload(q, hs.linkless(), true);
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
