// Hashed shading rendered through the GLSL lookup: forward and deferred
// images equal brute force's within the render tests' tolerance, the counts
// prove the GLSL lists conservative (same exact lower bound as brute force),
// the geometry mask and animated (incrementally updated) lights render the
// same, and the per-pixel light counts match the CPU mirror of the lookup.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/techniques/Registry.hpp"
#include "support/ImageCompare.hpp"
#include "support/BruteReference.hpp"
#include "support/DepthPoints.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

constexpr unsigned kW = test::kReferenceWidth, kH = test::kReferenceHeight;
const SceneInputs& inputs() { return test::referenceScene(); }

struct Rendered {
  FrameResult result;
  std::vector<float> image;
};

Rendered render(FrameRenderer& r, LightAssigner& a, Pipeline p, const Camera& cam) {
  Rendered out;
  out.result = r.render(cam, a, {p, true});
  out.image = r.targets().readColor();
  return out;
}

void expectMatchesBrute(const Rendered& h, const Rendered& b, const char* what) {
  SCOPED_TRACE(what);
  const auto diff = test::compareImages(h.image, b.image, 2.0 / 255.0);
  EXPECT_LT(diff.mean_abs, 0.002) << "max " << diff.max_abs;
  EXPECT_LT(diff.frac_over_tol, 0.005) << "max " << diff.max_abs;
  EXPECT_EQ(h.result.covered_pixels, b.result.covered_pixels);
  // Conservative: every light reaching a pixel's point was evaluated there.
  EXPECT_EQ(h.result.lower_bound, b.result.lower_bound);
  EXPECT_GE(h.result.light_evaluations, h.result.lower_bound);
  EXPECT_LT(h.result.light_evaluations, b.result.light_evaluations / 10);
}

TEST(HashedRender, ForwardAndDeferredMatchBruteForce) {
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  BruteForceAssigner brute;
  const Rendered bf = render(r, brute, Pipeline::Forward, cam);
  const Rendered bd = render(r, brute, Pipeline::Deferred, cam);
  hashed::HashedConfig params;
  HashedAssigner hf("hashed-forward", params), hd("hashed-deferred", params);
  const Rendered f = render(r, hf, Pipeline::Forward, cam);
  const Rendered d = render(r, hd, Pipeline::Deferred, cam);
  expectMatchesBrute(f, bf, "forward");
  expectMatchesBrute(d, bd, "deferred");
  // One fragment per pixel in deferred.
  EXPECT_EQ(d.result.fragment_evaluations, d.result.light_evaluations);
  EXPECT_GT(hd.memoryBytes(), 0u);
  EXPECT_FALSE(hd.stats().empty());

  // A second frame with unchanged lights reuses the structure: no rebuild.
  const std::size_t builds = hd.structure()->buildCount();
  render(r, hd, Pipeline::Deferred, cam);
  EXPECT_EQ(hd.structure()->buildCount(), builds);
}

// The GLSL reads the same lists as the CPU mirror: total evaluations over
// the covered pixels equal the CPU lookup at the reconstructed points.
TEST(HashedRender, GlslCountsEqualTheCpuLookup) {
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  hashed::HashedConfig params;
  params.node_size = "0.25r";
  params.start_depth = 2;
  HashedAssigner hf("hashed-forward", params);
  const Rendered f = render(r, hf, Pipeline::Forward, cam);
  const auto depth = r.targets().readDepth(false);
  const gpu::CameraParams cam_params = cam.params(kW, kH);
  std::uint64_t cpu = 0;
  std::size_t covered = 0;
  for (unsigned y = 0; y < kH; ++y)
    for (unsigned x = 0; x < kW; ++x) {
      const float dz = depth[y * kW + x];
      if (gpu::is_sky_depth(dz)) continue;
      ++covered;
      cpu += hf.structure()->linkless().lightsAt(glm::vec3(test::pixelWorldPoint(cam, cam_params, x, y, dz))).size();
    }
  EXPECT_EQ(covered, f.result.covered_pixels);
  // Reconstructed points differ from the interpolated ones by rounding, which
  // moves a few points across cell faces: allow 1%.
  EXPECT_NEAR(double(cpu), double(f.result.light_evaluations), 0.01 * double(cpu));
  std::string why;
  EXPECT_TRUE(hf.gpuMatchesHost(&why)) << why;
}

TEST(HashedRender, GeometryMaskMatchesBruteForce) {
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.back();
  BruteForceAssigner brute;
  const Rendered bf = render(r, brute, Pipeline::Forward, cam);
  const Rendered bd = render(r, brute, Pipeline::Deferred, cam);
  for (const char* node : {"0.25r", "0.5r"}) {  // 0.5r: the technique's default
    SCOPED_TRACE(node);
    hashed::HashedConfig params;
    params.geometry_mask = true;
    params.node_size = node;
    HashedAssigner hf("hashed-forward", params), hd("hashed-deferred", params);
    hf.setScene(&in.scene);
    hd.setScene(&in.scene);
    expectMatchesBrute(render(r, hf, Pipeline::Forward, cam), bf, "forward, masked");
    expectMatchesBrute(render(r, hd, Pipeline::Deferred, cam), bd, "deferred, masked");
  }
}

// render and bench (the registry's defaults) mask the octree with the scene's
// geometry unless told not to, and the masked default renders as brute force.
TEST(HashedRender, DefaultsMaskWithTheSceneGeometry) {
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  const TechniqueInfo& t = findTechnique("hashed-deferred");
  const auto masked = makeAssigner(t, test::runtime(), techniqueParams(t, {}, "--param"), &in.scene);
  const auto plain =
      makeAssigner(t, test::runtime(), techniqueParams(t, {{"geometry_mask", "off"}}, "--param"), &in.scene);
  auto& h = dynamic_cast<HashedAssigner&>(*masked);
  EXPECT_TRUE(h.config().geometry_mask);
  EXPECT_EQ(h.config().node_size, "0.5r");
  EXPECT_TRUE(h.config().octant_masks);
  EXPECT_FALSE(dynamic_cast<HashedAssigner&>(*plain).config().geometry_mask);
  BruteForceAssigner brute;
  const Rendered b = render(r, brute, Pipeline::Deferred, cam);
  const Rendered m = render(r, *masked, Pipeline::Deferred, cam);
  const Rendered p = render(r, *plain, Pipeline::Deferred, cam);
  expectMatchesBrute(m, b, "default (masked)");
  expectMatchesBrute(p, b, "--no-geometry-mask");
  EXPECT_EQ(m.result.missed_lights, 0u);
  EXPECT_EQ(p.result.missed_lights, 0u);
}

// Lights moving between frames: the incrementally updated GPU tables render
// exactly what a fresh structure renders, and match brute force; with and
// without the geometry mask (render's default).
void animatedLightsMatchAFreshBuild(bool geometry_mask) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  auto lights = in.lights;
  r.setLights(lights);
  const Camera& cam = in.cameras.frames.front();
  hashed::HashedConfig params;
  params.geometry_mask = geometry_mask;
  HashedAssigner animated("hashed-deferred", params);
  animated.setScene(&in.scene);
  animated.config().bounds_padding = 0.1;
  render(r, animated, Pipeline::Deferred, cam);
  int partial_uploads = 0;
  for (int frame = 0; frame < 4; ++frame) {
    for (int i = 0; i < 60; ++i) {  // ~6% of the lights move, a few are removed and added
      auto& l = lights[rng() % lights.size()];
      l.position_radius.x += float(rng() % 1000) / 1000.0f - 0.5f;
      l.position_radius.z += float(rng() % 1000) / 1000.0f - 0.5f;
    }
    const std::size_t victim = rng() % lights.size();
    lights[victim] = lights.back();
    lights.pop_back();
    lights.push_back(lights[rng() % lights.size()]);
    lights.back().position_radius.y += 0.3f;
    r.setLights(lights);
    render(r, animated, Pipeline::Deferred, cam);
    // Only edited words were uploaded, and they leave the GPU copy exact.
    std::string why;
    EXPECT_TRUE(animated.gpuMatchesHost(&why)) << "frame " << frame << ": " << why;
    partial_uploads += animated.lastUploadBytes() < animated.memoryBytes();
  }
  // A table rehashed to a new size re-uploads everything; the others upload
  // just the edited words.
  EXPECT_GT(partial_uploads, 0);
  EXPECT_EQ(animated.structure()->buildCount(), 1u) << animated.structure()->lastUpdate().reason;
  // Stats keys go into JSON as they are: no indentation (that is the table
  // printer's), build and update keys both present after updates.
  std::set<std::string> keys;
  for (const auto& [k, v] : animated.stats()) {
    EXPECT_FALSE(k.empty() || k.front() == ' ' || k.back() == ' ') << "'" << k << "'";
    EXPECT_TRUE(keys.insert(k).second) << "duplicate stats key '" << k << "'";
  }
  EXPECT_TRUE(keys.count("build bounds ms") && keys.count("update lights moved"));
  const Rendered a = render(r, animated, Pipeline::Deferred, cam);
  HashedAssigner fresh("hashed-deferred", params);
  fresh.setScene(&in.scene);
  const Rendered f = render(r, fresh, Pipeline::Deferred, cam);
  BruteForceAssigner brute;
  const Rendered b = render(r, brute, Pipeline::Deferred, cam);
  // Fresh bounds differ from the animated structure's padded ones, so the
  // cells differ: compare both with brute force, and the counts' bound.
  expectMatchesBrute(a, b, "animated");
  expectMatchesBrute(f, b, "fresh");
}

TEST(HashedRender, AnimatedLightsMatchAFreshBuild) { animatedLightsMatchAFreshBuild(false); }
TEST(HashedRender, AnimatedMaskedLightsMatchAFreshBuild) { animatedLightsMatchAFreshBuild(true); }

TEST(HashedRender, NoLightsGivesAmbientOnly) {
  test::glContext();
  const auto& in = inputs();
  FrameRenderer r(test::runtime(), in.scene, 64, 36);
  r.setLights({});
  hashed::HashedConfig params;
  HashedAssigner h("hashed-deferred", params);
  const FrameResult res = r.render(in.cameras.frames.front(), h, {Pipeline::Deferred, true});
  EXPECT_EQ(res.light_evaluations, 0u);
  EXPECT_EQ(res.lower_bound, 0u);
}

}  // namespace
}  // namespace ml
