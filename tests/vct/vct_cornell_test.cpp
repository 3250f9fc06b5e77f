// Voxel cone tracing on the Cornell box (data/cornell, its 4 lights) against
// the Embree one-bounce reference of the same transport (no visibility in the
// bounce light): the indirect image's relative RMSE over covered pixels
// (indirectRelRmse) stays under kCornellBound; the same run with the cone
// weights broken (each 1 instead of pi / count) must exceed it. The bound
// comes from measurement (see docs/vct-compute.md), with margin. (Cones that
// sample level 0 only were the broken mip filter here until the steps stopped
// outgrowing the sampled level: that march became a fair estimate, 0.203
// against the mips' 0.285 then, and no longer a failure to detect; the filters
// themselves are checked against their twins, tests/vct/vct_mips_test.cpp.)
// With --vct-shadows voxel (visibility through level-0 opacity) against the
// reference with visibility from the bounce points (--gi-shadows ray): under
// kCornellShadowBound, and through the command with the transports reported.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gl/FrameRenderer.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/scene/LightSet.hpp"
#include "host/vct/VctGiPass.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kW = 160, kH = 90;
constexpr double kCornellBound = 0.24;  // measured 0.151 (64^3 x 5, anisotropic, 9 x 45 deg, scale 0.5)
constexpr double kCornellIsotropicBound = 0.25;  // measured 0.170 (64^3 x 5, isotropic, 9 x 45 deg, scale 0.5)
constexpr double kCornellShadowBound = 0.25;  // measured 0.158 (64^3 x 5, anisotropic, --vct-shadows voxel)

struct Cornell {
  Scene scene;
  std::vector<gpu::PointLight> lights;
  Camera camera;
  std::vector<float> reference, shadowed_reference;  // --gi-shadows none, ray (traced on first use)
  std::vector<float> two_bounce_reference;           // --gi-bounces 2 (traced on first use)
  Cornell() {
    const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
    scene = loadGltfScene(dir + "cornell.gltf");
    lights = loadLightsJson(dir + "lights.json");
    camera = loadCameraJson(dir + "camera.json").frames.front();
    reference = traceIndirectReference(scene, lights, camera, kW, kH, {256, 23, false}).rgba;
  }
  const std::vector<float>& referenceFor(const VctGiSettings& s) {
    if (s.bounces == 2) {
      if (two_bounce_reference.empty())
        two_bounce_reference = traceIndirectReference(scene, lights, camera, kW, kH, {256, 23, false, 2}).rgba;
      return two_bounce_reference;
    }
    if (s.shadows != "voxel") return reference;
    if (shadowed_reference.empty())
      shadowed_reference = traceIndirectReference(scene, lights, camera, kW, kH, {256, 23, true}).rgba;
    return shadowed_reference;
  }
};

Cornell& cornell() {
  static Cornell c;
  return c;
}

// The indirect image of one deferred w x h frame with settings `s`.
std::vector<float> vctImage(const VctGiSettings& s, Pipeline pipeline = Pipeline::Deferred, unsigned w = kW,
                            unsigned h = kH) {
  test::glContext();
  Cornell& c = cornell();
  FrameRenderer r(test::runtime(), c.scene, w, h);
  r.setLights(c.lights);
  BruteForceAssigner brute;
  VctGiPass gi(test::runtime(), s, c.scene.bounds);
  FrameOptions o{pipeline, false, true, &gi};
  r.render(c.camera, brute, o);
  return gi.indirectRgba();
}

IndirectError vctError(const VctGiSettings& s, Pipeline pipeline = Pipeline::Deferred) {
  const std::vector<float>& reference = cornell().referenceFor(s);
  const std::vector<float> img = vctImage(s, pipeline);
  double sum = 0, ref = 0;
  for (std::size_t i = 0; i < img.size(); i += 4)
    if (img[i + 3] > 0 && reference[i + 3] > 0)
      for (int k = 0; k < 3; ++k) sum += img[i + k], ref += reference[i + k];
  const IndirectError e = indirectRelRmse(img, reference);
  std::printf("shadows %s bounces %u voxels %u levels %u aniso %d cones %u aperture %g lod bias %g scale %g broken "
              "%d: rel RMSE %.4f, mean ratio %.3f\n",
              s.shadows.c_str(), s.bounces, s.grid.voxels, s.grid.levels, int(s.grid.anisotropic), s.cones,
              double(s.aperture_deg), double(s.lod_bias), double(s.gi_scale), int(s.broken), e.rel_rmse,
              ref > 0 ? sum / ref : 0.0);
  return e;
}

// Most pixels covered, none mismatched, and the error under `bound`.
void expectNearTheReference(const VctGiSettings& s, double bound) {
  const IndirectError e = vctError(s);
  EXPECT_GT(e.pixels, kW * kH / 2);
  EXPECT_EQ(e.mismatched, 0u);
  EXPECT_GE(e.rel_rmse, 0.0);
  EXPECT_LT(e.rel_rmse, bound);
}

TEST(VctCornell, IndirectImageIsNearTheReferenceAndBrokenTracesAreNot) {
  VctGiSettings s;
  s.grid.anisotropic = true;
  expectNearTheReference(s, kCornellBound);
  s.broken = ConeBreak::Weights;
  EXPECT_GT(vctError(s).rel_rmse, kCornellBound) << "broken cone weights pass the bound";
}

// Isotropic voxels (one RGBA per voxel): the mip filter composites child
// pairs along each axis in both orders, keeps the brighter order and the most
// opaque axis, so the box's one-voxel walls stay opaque at coarse levels.
// Measured 0.170 (image sum 0.89 of the reference's; 0.167 and 0.91 at lod
// bias 1.25; 0.194 and 0.96 with
// the former sunflower cone set, lod bias 1 and no interleaved turns); with the mean of both
// orders 0.272 (0.80: once a 0.1 m slab's lit face and dark back share a
// voxel, the mean gave every side half the lit face's light; 0.339 and 0.74
// at 4 levels before the cones' changes of vct_cones.glsl); the former filter (the mean
// of the 8 children) left the walls half transparent (0.66 at 64^3 in the
// 320x180 frame sweep, bench/RESULTS-vct.md), the mean of the three axes
// instead of the most opaque 0.438 (before the edge clamp and the step cap).
// Broken cone weights must fail kCornellIsotropicBound.
TEST(VctCornell, IsotropicIndirectImageIsNearTheReference) {
  VctGiSettings s;
  s.grid.anisotropic = false;
  expectNearTheReference(s, kCornellIsotropicBound);
  s.broken = ConeBreak::Weights;
  EXPECT_GT(vctError(s).rel_rmse, kCornellIsotropicBound) << "broken cone weights pass the bound";
}

// --cone-lod-bias reaches the trace: at bias 0 the cones read levels twice
// their width's worth coarser than at the default, and the image is farther
// from the reference by at least kBiasGain. Measured 0.151 at 1.5 against
// 0.231 at 0 (64^3, 160x90).
constexpr double kBiasGain = 0.02;
TEST(VctCornell, TheConeLodBiasReachesTheTrace) {
  VctGiSettings s;
  s.grid.anisotropic = true;
  const double sharp = vctError(s).rel_rmse;
  s.lod_bias = 0.0f;
  EXPECT_GT(vctError(s).rel_rmse, sharp + kBiasGain) << "bias 0 traces as the default";
}

// A finer grid is a better estimate: on the frame (320x320, the
// box's camera) the error without the reference's own noise
// (compareWithReference, 256 samples, a fresh seed) falls from 32^3 to 64^3 to 128^3
// (--levels auto, anisotropic, 9 cones of 45 degrees), each step by at least
// kFinerGain. Measured 0.134, 0.130, 0.118 with the ring cone set, lod bias
// 1.5 and interleaved turns (at bias 1.25 0.139, 0.132, 0.121; 0.156, 0.147,
// 0.138 without the turns; 0.164,
// 0.159, 0.141 with the sunflower set at bias 1; against
// 4096 samples 0.164, 0.159, 0.142); before the cones read the level half their width, the
// coarsest level kept its world size, the trilinear opacity stopped leaking
// and the faces' colours were mixed by optical depth: 0.197, 0.227, 0.185
// (4 levels). At 160x90 (an 80x45 trace) 64^3 is still above 32^3.
constexpr double kFinerGain = 0.002;
TEST(VctCornell, NoiseCorrectedErrorFallsAsTheVoxelsGetFiner) {
  constexpr unsigned kSide = 320;
  Cornell& c = cornell();
  const std::uint64_t seed = test::freshSeed();  // the reference's noise is taken out, so any seed must do
  SCOPED_TRACE("reference seed=" + std::to_string(seed));
  std::printf("reference seed %llu\n", static_cast<unsigned long long>(seed));
  const IndirectImage ref = traceIndirectReference(c.scene, c.lights, c.camera, kSide, kSide, {256, seed, false});
  double coarser = 0;
  for (unsigned voxels : {32u, 64u, 128u}) {
    VctGiSettings s;
    s.grid = {voxels, autoLevels(voxels), true};
    const IndirectComparison e = compareWithReference(vctImage(s, Pipeline::Deferred, kSide, kSide), ref);
    std::printf("%u^3 x %u levels: rel RMSE %.4f, reference noise %.4f, without it %.4f\n", voxels, s.grid.levels,
                e.error.rel_rmse, e.ref_noise, e.corrected);
    ASSERT_GT(e.ref_noise, 0.0);
    ASSERT_GT(e.corrected, 0.0);
    if (voxels > 32) {
      EXPECT_LT(e.corrected, coarser - kFinerGain) << voxels << "^3 against " << voxels / 2 << "^3";
    }
    coarser = e.corrected;
  }
}

// --gi-bounces 2: each voxel gathers the first bounce's light through the
// cones and the frame traces the sum; against the two-bounce reference it
// stays under kCornellBound, where the one-bounce image (what the second
// bounce adds is 32% of the two-bounce light) does not. Measured 0.148 (mean
// ratio 0.89) against 0.403.
TEST(VctCornell, TwoBouncesAreNearTheTwoBounceReference) {
  VctGiSettings s;
  s.bounces = 2;
  expectNearTheReference(s, kCornellBound);
  const std::vector<float>& two = cornell().referenceFor(s);
  s.bounces = 1;
  const IndirectError one = indirectRelRmse(vctImage(s), two);
  std::printf("one bounce against the two-bounce reference: rel RMSE %.4f\n", one.rel_rmse);
  EXPECT_GT(one.rel_rmse, kCornellBound) << "the second bounce adds nothing the bound sees";
}

TEST(VctCornell, VoxelShadowsAreNearTheShadowedReference) {
  VctGiSettings s;
  s.grid.anisotropic = true;
  s.shadows = "voxel";
  expectNearTheReference(s, kCornellShadowBound);
}

// Runs this build's binary on the Cornell box with --gi vct --anisotropic
// --gi-reference and `extra`, writing f.png and f.json into `tmp`.
nlohmann::json renderCornell(const test::TempDir& tmp, const std::string& extra) {
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  const std::string out = tmp.file("f.png"), stats = tmp.file("f.json");
  const auto r = test::runManylights("render --scene " + dir + "cornell.gltf --lights " + dir + "lights.json --camera " +
                                     dir + "camera.json --technique tiled-forward --size 160x90 --frames 1 --warmup 0 "
                                     "--gi vct --anisotropic --gi-reference --gi-samples 64 --out " + out +
                                     " --stats-json " + stats + extra);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return nullptr;
  return nlohmann::json::parse(std::ifstream(stats));
}

// The command (this build's binary, a separate process): the frame, the
// indirect image, its ambient occlusion and the reference are written, and the
// stats JSON has the vct passes, voxel_bytes and gi_rel_rmse under the bound.
TEST(VctCornell, RenderCommandReportsTheErrorAndThePasses) {
  test::TempDir tmp;
  const auto j = renderCornell(tmp, "");
  ASSERT_FALSE(j.is_null());
  for (const char* f : {"f_gi_vct.exr", "f_gi_vct.png", "f_gi_vct_ao.png", "f_gi_reference.exr", "f.png"})
    EXPECT_TRUE(std::filesystem::exists(tmp.file(f))) << f;
  for (const char* pass : {"vct-voxelize", "vct-inject", "vct-mips", "vct-trace", "vct-upsample"})
    EXPECT_TRUE(j.at("passes").contains(pass)) << pass;
  EXPECT_EQ(j.at("voxel_bytes").get<std::size_t>(), voxelBytes({64, autoLevels(64), true}));
  EXPECT_GT(j.at("gi_rel_rmse").get<double>(), 0.0);
  EXPECT_LT(j.at("gi_rel_rmse").get<double>(), kCornellBound);
  EXPECT_EQ(j.at("gi_vct").at("cones").get<int>(), 9);
  EXPECT_EQ(j.at("gi_shadows"), "none");
}

// --vct-shadows voxel: the reference is traced with --gi-shadows ray unasked,
// both transports say so, and the error stays under its bound.
TEST(VctCornell, RenderCommandWithVoxelShadowsTracesTheShadowedReference) {
  test::TempDir tmp;
  const auto j = renderCornell(tmp, " --vct-shadows voxel");
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j.at("gi_vct").at("vct_shadows"), "voxel");
  EXPECT_EQ(j.at("gi_shadows"), "ray");
  EXPECT_NE(j.at("gi_transport").get<std::string>().find("--vct-shadows voxel"), std::string::npos);
  EXPECT_NE(j.at("gi_reference_transport").get<std::string>().find("--gi-shadows ray"), std::string::npos);
  EXPECT_GT(j.at("gi_rel_rmse").get<double>(), 0.0);
  EXPECT_LT(j.at("gi_rel_rmse").get<double>(), kCornellShadowBound);
}

}  // namespace
}  // namespace ml::vct
