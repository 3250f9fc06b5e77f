// vct::VctPipeline, one VCT update per frame (voxelize -> inject -> mips on
// one VoxelVolume), both kernel shapes, hashed lists and brute force:
//  - on the Cornell box and on random triangle soups with random lights, the
//    chained result equals the C++ twins run on the voxelization's own output:
//    level 0 = injectTwin(accum) (injection's tolerance, as in
//    vct_volume_test: exact where the device divides and takes square roots
//    correctly rounded, else 1e-5 relative; hashed lists only change the
//    summation order of non-negative terms, 1e-5 relative), and the mips equal
//    mipIsotropicTwin / mipAnisotropicTwin of the device's level 0 bit for bit;
//  - a light move reruns inject and mips only (no `vct-voxelize` pass, one
//    voxelization counted) and the volume follows the new lights; with
//    `revoxelize` every update voxelizes, from cleared sums: the same
//    geometry gives the same sums and volume bit for bit (not doubled).
// The radiance and anisotropic volumes are poisoned (NaN) before each update.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "gl/SceneGpu.hpp"
#include "host/scene/LightSet.hpp"
#include "host/vct/InjectTwin.hpp"
#include "host/vct/VctPipeline.hpp"
#include "host/vct/VoxelMipsReference.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/shape_support.hpp"
#include "support/FpTolerance.hpp"
#include "support/RandomSoup.hpp"
#include "support/SharedBufferIo.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;
using test::downloadAll;
using test::firstBitDifference;
using test::poison;

// "" when equal, else the first mismatch.
std::string compareLevel0(const std::vector<F4>& got, const std::vector<F4>& want, bool exact) {
  for (std::size_t i = 0; i < want.size(); ++i) {
    const float g[4] = {got[i].x, got[i].y, got[i].z, got[i].w}, w[4] = {want[i].x, want[i].y, want[i].z, want[i].w};
    for (int c = 0; c < 4; ++c) {
      const bool ok = exact ? test::floatsMatch(g[c], w[c])
                            : std::fabs(g[c] - w[c]) <= 1e-5f * std::fabs(w[c]) + 1e-7f;
      if (!ok)
        return "voxel " + std::to_string(i) + " component " + std::to_string(c) + ": got " + std::to_string(g[c]) +
               " want " + std::to_string(w[c]);
    }
  }
  return "";
}

struct Param {
  KernelShape shape;
  bool brute;
};

class VctPipelineTest : public ::testing::TestWithParam<Param> {
 protected:
  VctPipelineOptions options(VoxelGridSettings grid) const {
    VctPipelineOptions o;
    o.grid = grid;
    o.brute_force = GetParam().brute;
    o.compute.shape = GetParam().shape;
    return o;
  }

  // One poisoned update, then the volume against the twins on its own accum.
  // Returns the device's radiance volume.
  std::vector<F4> updateAndCheck(VctPipeline& p, const SceneGpu& scene, const std::vector<gpu::PointLight>& lights,
                                 PassTimings& t) {
    VoxelVolume& v = p.volume();
    poison(&v.radiance());
    poison(v.anisotropic());
    p.update(scene, lights, t);
    const VoxelGridSettings& s = v.settings();
    const std::size_t n0 = std::size_t(s.voxels) * s.voxels * s.voxels;
    const auto accum = downloadAll<gpu::VoxelAccum>(v.accum(), n0);
    const auto got = downloadAll<F4>(v.radiance(), radianceBytes(s) / sizeof(F4));
    const auto want0 = injectTwin(accum, v.params(), lights);
    const bool exact = GetParam().brute && test::exactDivideSqrt();
    EXPECT_EQ(compareLevel0(got, want0, exact), "") << (GetParam().brute ? "brute force" : "hashed lists");
    std::vector<F4> want(got.begin(), got.begin() + std::ptrdiff_t(n0));
    want.resize(got.size());
    mipIsotropicTwin(want, s.voxels, s.levels);
    EXPECT_EQ(firstBitDifference(got, want), got.size()) << "isotropic mips";
    if (s.anisotropic) {
      std::vector<F4> want_aniso;
      mipAnisotropicTwin(want, want_aniso, s.voxels, s.levels);
      const auto got_aniso = downloadAll<F4>(*v.anisotropic(), want_aniso.size());
      EXPECT_EQ(firstBitDifference(got_aniso, want_aniso), want_aniso.size()) << "anisotropic mips";
    }
    return got;
  }
};

bool anyLit(const std::vector<F4>& radiance, std::size_t n0) {
  for (std::size_t i = 0; i < n0; ++i)
    if (radiance[i].x > 0 || radiance[i].y > 0 || radiance[i].z > 0) return true;
  return false;
}

TEST_P(VctPipelineTest, CornellBoxEqualsTheTwinsOnItsVoxelization) {
  test::glContext();
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  const Scene scene = loadGltfScene(dir + "cornell.gltf");
  const auto lights = loadLightsJson(dir + "lights.json");
  ASSERT_FALSE(lights.empty());
  SceneGpu gpu_scene(scene);
  VctPipeline p(test::runtime(), options({32, 4, true}), scene.bounds);
  PassTimings t;
  const auto got = updateAndCheck(p, gpu_scene, lights, t);
  EXPECT_TRUE(anyLit(got, 32 * 32 * 32)) << "no voxel lit: the comparison would prove nothing";
  EXPECT_GT(t.get("vct-voxelize"), 0.0);
  for (const char* pass : {"vct-inject", "vct-mips"}) {
    bool found = false;
    for (const auto& e : t.entries()) found |= e.first == pass;
    EXPECT_TRUE(found) << pass << " missing from the pass timings";
  }
}

TEST_P(VctPipelineTest, RandomScenesEqualTheTwinsAndLightMovesSkipVoxelization) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const unsigned edges[] = {1, 2, 4, 8, 16};
  const unsigned edge = edges[rng() % 5];
  const unsigned levels = 1 + unsigned(rng() % (log2Exact(edge) + 1));
  const bool aniso = rng() % 2 && levels > 1;
  const std::size_t light_counts[] = {0, 1, 7, 33, 64};
  const std::size_t light_count = light_counts[rng() % 5];
  SCOPED_TRACE("edge " + std::to_string(edge) + " levels " + std::to_string(levels) + " anisotropic " +
               std::to_string(aniso) + " lights " + std::to_string(light_count));
  const Scene scene = test::randomSoup(rng, 10 + rng() % 40);  // enough orientations that some face the lights
  SceneGpu gpu_scene(scene);
  VctPipeline p(test::runtime(), options({edge, levels, aniso}), scene.bounds);
  PassTimings first, second;
  const auto before = updateAndCheck(p, gpu_scene, test::randomLightsIn(rng, light_count, scene.bounds), first);
  // The lights move (every one of them, and their number changes).
  const auto moved = test::randomLightsIn(rng, 8 + rng() % 40, scene.bounds);
  const auto after = updateAndCheck(p, gpu_scene, moved, second);
  EXPECT_EQ(p.voxelizations(), 1u);
  EXPECT_EQ(p.updates(), 2u);
  EXPECT_GT(first.get("vct-voxelize"), 0.0);
  for (const auto& e : second.entries()) EXPECT_NE(e.first, "vct-voxelize") << "static geometry voxelized twice";
  EXPECT_TRUE(anyLit(after, std::size_t(edge) * edge * edge)) << "no voxel lit by the moved lights";
  EXPECT_NE(firstBitDifference(before, after), before.size()) << "the volume did not follow the lights";
}

TEST_P(VctPipelineTest, RevoxelizeVoxelizesEveryUpdate) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = test::randomSoup(rng, 20);
  SceneGpu gpu_scene(scene);
  VctPipelineOptions o = options({8, 2, false});
  o.revoxelize = true;
  VctPipeline p(test::runtime(), o, scene.bounds);
  const auto lights = test::randomLightsIn(rng, 9, scene.bounds);
  const std::size_t n0 = 8 * 8 * 8;
  std::vector<gpu::VoxelAccum> accum[2];
  std::vector<F4> radiance[2];
  for (int i = 0; i < 2; ++i) {
    PassTimings t;
    radiance[i] = updateAndCheck(p, gpu_scene, lights, t);
    accum[i] = downloadAll<gpu::VoxelAccum>(p.volume().accum(), n0);
    EXPECT_GT(t.get("vct-voxelize"), 0.0) << "update " << i;
  }
  EXPECT_EQ(p.voxelizations(), 2u);
  // The sums restart from zero: a second voxelization adding onto the first
  // would double every count and albedo sum (the resolved albedo, a mean,
  // would not show it, so the raw sums are compared).
  bool filled = false;
  for (const gpu::VoxelAccum& a : accum[0]) filled |= a.albedo_count[3] > 0;
  EXPECT_TRUE(filled) << "nothing voxelized: the comparison would prove nothing";
  std::size_t first_diff = n0;
  for (std::size_t i = 0; i < n0 && first_diff == n0; ++i)
    if (std::memcmp(&accum[0][i], &accum[1][i], sizeof(gpu::VoxelAccum)) != 0) first_diff = i;
  EXPECT_EQ(first_diff, n0) << "re-voxelizing the same geometry changed voxel " << first_diff << " (count "
                            << accum[0][std::min(first_diff, n0 - 1)].albedo_count[3] << " -> "
                            << accum[1][std::min(first_diff, n0 - 1)].albedo_count[3] << ")";
  EXPECT_EQ(firstBitDifference(radiance[0], radiance[1]), radiance[0].size()) << "same geometry and lights";
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctPipelineTest,
                         ::testing::Values(Param{KernelShape::CpuChunked, false}, Param{KernelShape::CpuChunked, true},
                                           Param{KernelShape::GpuWorkGroup, false},
                                           Param{KernelShape::GpuWorkGroup, true}),
                         [](const auto& info) {
                           return test::shapeLabel(info.param.shape) + (info.param.brute ? "_brute" : "_hashed");
                         });

}  // namespace
}  // namespace ml::vct
