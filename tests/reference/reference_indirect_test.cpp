// The ray-traced indirect reference (host/reference): its light grid finds
// exactly the lights brute force finds; inside a closed sphere with a point
// light at its centre the one-bounce value is analytic; the estimate converges
// with the sample count; shadow rays only remove light; its camera sees what
// the GL renderer sees; `render --gi` checks its flags and writes its files.
//
// Sphere of radius R, light at the centre (intensity I, radius r > R): with the
// interpolated normals of a tessellation whose vertices lie on the sphere, the
// normal at a point y is -y/|y| exactly, so cos = 1 and E(y) = I (1 - |y|/r)^2,
// |y| in [h, R] (h: the nearest triangle plane's distance from the centre).
// Uniform albedo a: indirect = a * a * E, so every pixel lies in
// [a^2 I (1-R/r)^2, a^2 I (1-h/r)^2] whatever the samples (a furnace bound).
// A cap of albedo c on a sphere of albedo b: from any point of a sphere the
// cosine-weighted (form-factor) share of any region is its area / the
// sphere's area (cos_x = cos_y = d / 2R), so indirect = b E (c F + b (1 - F)),
// F = cap area / sphere area; uniform hemisphere sampling would not give it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <filesystem>
#include <fstream>
#include <random>
#include <nlohmann/json.hpp>
#include <set>

#include "gl/FrameRenderer.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/assign/BruteForceAssigner.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/reference/LightSphereGrid.hpp"
#include "host/util/Error.hpp"
#include "host/util/ImageIO.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/InProcessCli.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

glm::vec3 pos(const gpu::PointLight& l) { return {l.position_radius.x, l.position_radius.y, l.position_radius.z}; }

std::vector<gpu::PointLight> randomLights(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<float> p(-10.0f, 10.0f), r(0.01f, 3.0f);
  std::vector<gpu::PointLight> out(n);
  for (auto& l : out) l = {{p(rng), p(rng), p(rng), r(rng)}, {1, 1, 1, 0}};
  if (n > 2) out[n - 1] = out[0];                       // a duplicate
  if (n > 3) out[1].position_radius.w = 40.0f;          // one covering everything
  if (n > 4) out[2].position_radius.w = 1e-4f;          // a tiny one
  return out;
}

TEST(ReferenceLightSphereGrid, CandidatesHoldExactlyTheLightsReachingAPoint) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<float> p(-14.0f, 14.0f);
  for (std::size_t n : {0u, 1u, 5u, 127u, 1025u, 10000u}) {
    SCOPED_TRACE("lights=" + std::to_string(n));
    const auto lights = randomLights(rng, n);
    const LightSphereGrid grid(lights);
    std::size_t hits = 0;
    for (int k = 0; k < 2000; ++k) {
      glm::vec3 q(p(rng), p(rng), p(rng));
      if (k < 20 && n > 0) q = pos(lights[k % n]);  // light centres and the tiny light
      std::set<std::uint32_t> brute, found;
      for (std::uint32_t i = 0; i < n; ++i)
        if (glm::length(q - pos(lights[i])) < lights[i].position_radius.w) brute.insert(i);
      std::size_t visits = 0;
      grid.forEachCandidate(q, [&](std::uint32_t i) {
        ++visits;
        if (glm::length(q - pos(lights[i])) < lights[i].position_radius.w) found.insert(i);
      });
      ASSERT_EQ(found, brute) << "point " << k;
      EXPECT_LE(found.size(), visits);
      hits += brute.size();
    }
    if (n > 0) {
      EXPECT_GT(hits, 0u);
    }
  }
}

// A UV sphere seen from inside, normals = the radial direction; triangles whose
// centroid lies above y = cap_y get material 1, the others material 0.
Scene insideSphere(float radius, unsigned segments, unsigned rings, float cap_y, glm::vec4 base, glm::vec4 cap) {
  Scene s;
  s.source = "sphere";
  for (unsigned r = 0; r <= rings; ++r)
    for (unsigned k = 0; k <= segments; ++k) {
      const float th = 3.14159265f * r / rings, ph = 6.28318531f * k / segments;
      const glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
      s.vertices.push_back({radius * d, -d, {0, 0}});
      s.bounds.extend(radius * d);
    }
  std::vector<std::uint32_t> tris[2];
  for (unsigned r = 0; r < rings; ++r)
    for (unsigned k = 0; k < segments; ++k) {
      const std::uint32_t a = r * (segments + 1) + k, b = a + 1, c = a + segments + 1, d = c + 1;
      const std::uint32_t quad[2][3] = {{a, c, b}, {b, c, d}};
      for (const auto& t : quad) {
        const float cy = (s.vertices[t[0]].position.y + s.vertices[t[1]].position.y + s.vertices[t[2]].position.y) / 3;
        tris[cy > cap_y].insert(tris[cy > cap_y].end(), t, t + 3);
      }
    }
  for (int m = 0; m < 2; ++m) {
    s.batches.push_back({std::uint32_t(s.indices.size()), std::uint32_t(tris[m].size()), std::uint32_t(m)});
    s.indices.insert(s.indices.end(), tris[m].begin(), tris[m].end());
  }
  s.materials = {{base, -1}, {cap, -1}};
  return s;
}

// Nearest triangle plane and the share of the area in material 1.
void sphereFacts(const Scene& s, double& h_min, double& cap_share) {
  h_min = 1e30;
  double area[2] = {0, 0};
  for (const DrawBatch& b : s.batches)
    for (std::uint32_t i = b.first_index; i < b.first_index + b.index_count; i += 3) {
      const glm::dvec3 p0 = s.vertices[s.indices[i]].position, p1 = s.vertices[s.indices[i + 1]].position,
                       p2 = s.vertices[s.indices[i + 2]].position;
      const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
      if (glm::length(n) < 1e-12) continue;
      h_min = std::min(h_min, std::abs(glm::dot(glm::normalize(n), p0)));
      area[b.material] += 0.5 * glm::length(n);
    }
  cap_share = area[1] / (area[0] + area[1]);
}

Camera insideCamera(glm::vec3 look) {
  Camera c;
  c.eye = glm::vec3(0.0f);
  c.center = look;
  c.up = std::abs(look.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  c.fovy_degrees = 60.0f;
  c.near_plane = 0.01f;
  c.far_plane = 10.0f;
  return c;
}

TEST(ReferenceIndirect, UniformSphereMeetsTheFurnaceBound) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<float> u(0.2f, 0.9f), dir(-1.0f, 1.0f);
  const float R = 1.0f, r = R * (1.2f + 2.0f * u(rng)), I = 4.0f * u(rng), a = u(rng);
  const Scene s = insideSphere(R, 96, 48, 2.0f, {a, a, a, 1}, {a, a, a, 1});
  double h = 0, share = 0;
  sphereFacts(s, h, share);
  const double lo = a * a * I * std::pow(1 - R / r, 2), hi = a * a * I * std::pow(1 - h / r, 2);
  ASSERT_LT(hi / lo, 1.01);  // the bound is tight
  const std::vector<gpu::PointLight> light = {{{0, 0, 0, r}, {I, I, I, 0}}};
  for (bool shadows : {false, true}) {
    const IndirectImage img = traceIndirectReference(s, light, insideCamera({dir(rng), dir(rng), dir(rng)}), 24, 16,
                                                     {8, seed, shadows});
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) {
      ASSERT_EQ(img.rgba[i + 3], 1.0f) << "pixel " << i / 4 << " missed the sphere";
      for (int c = 0; c < 3; ++c) {
        ASSERT_GE(img.rgba[i + c], lo * (1 - 1e-4)) << "pixel " << i / 4 << " shadows " << shadows;
        ASSERT_LE(img.rgba[i + c], hi * (1 + 1e-4)) << "pixel " << i / 4 << " shadows " << shadows;
      }
    }
  }
}

// The same furnace with k bounces: every hit of a path has the same direct
// radiance B = a I w (w between the bound's ends), so a path that stays in
// the closed sphere brings back B (1 + a + .. + a^(k-1)) and the pixel a times
// that, exactly (no noise: each continuation only adds a factor of the bound).
// A missing continuation, a wrong albedo weight or one bounce too many or too
// few leaves the bound: the bound is 1% wide (hi / lo), the last bounce adds
// a^(k-1) / (1 + .. + a^(k-2)) >= 7% for a >= 0.5 and k <= 4.
TEST(ReferenceIndirect, UniformSphereHoldsTheFurnaceBoundForEveryBounceCount) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<float> u(0.2f, 0.9f), albedo(0.5f, 0.9f), dir(-1.0f, 1.0f);
  const float R = 1.0f, r = R * (1.2f + 2.0f * u(rng)), I = 4.0f * u(rng), a = albedo(rng);
  const Scene s = insideSphere(R, 96, 48, 2.0f, {a, a, a, 1}, {a, a, a, 1});
  double h = 0, share = 0;
  sphereFacts(s, h, share);
  const std::vector<gpu::PointLight> light = {{{0, 0, 0, r}, {I, I, I, 0}}};
  ASSERT_LT(std::pow(1 - h / r, 2) / std::pow(1 - R / r, 2), 1.01);  // the bound is tight
  double sum = 0;
  for (unsigned k = 1; k <= 4; ++k) {
    sum += std::pow(double(a), k - 1);
    const double lo = a * a * I * std::pow(1 - R / r, 2) * sum, hi = a * a * I * std::pow(1 - h / r, 2) * sum;
    const IndirectImage img = traceIndirectReference(s, light, insideCamera({dir(rng), dir(rng), dir(rng)}), 16, 12,
                                                     {8, seed, k % 2 == 0, k});
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) {
      ASSERT_EQ(img.rgba[i + 3], 1.0f) << "pixel " << i / 4 << " missed the sphere";
      for (int c = 0; c < 3; ++c) {
        ASSERT_GE(img.rgba[i + c], lo * (1 - 1e-4)) << "pixel " << i / 4 << " bounces " << k;
        ASSERT_LE(img.rgba[i + c], hi * (1 + 1e-4)) << "pixel " << i / 4 << " bounces " << k;
      }
    }
  }
  EXPECT_THROW(traceIndirectReference(s, light, insideCamera({0, 0, 1}), 4, 4, {1, seed, false, 0}), UserError);
  EXPECT_THROW(traceIndirectReference(s, light, insideCamera({0, 0, 1}), 4, 4, {1, seed, false, kMaxIndirectBounces + 1}),
               UserError);
}

TEST(ReferenceIndirect, CapOnASphereGetsItsFormFactor) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const float R = 1.0f, r = 3.0f, I = 2.0f, b = 0.4f, c = 0.95f;
  const Scene s = insideSphere(R, 96, 48, 0.5f, {b, b, b, 1}, {c, c, c, 1});  // cap: 60 degrees around +y
  double h = 0, share = 0;
  sphereFacts(s, h, share);
  ASSERT_NEAR(share, 0.25, 0.01);
  const std::vector<gpu::PointLight> light = {{{0, 0, 0, r}, {I, I, I, 0}}};
  const IndirectImage img = traceIndirectReference(s, light, insideCamera({0.05f, -1.0f, 0.02f}), 32, 24, {256, seed, false});
  double sum = 0;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4) sum += img.rgba[i];
  const double mean = sum / double(img.rgba.size() / 4);
  const double e_lo = I * std::pow(1 - R / r, 2), e_hi = I * std::pow(1 - h / r, 2);
  const double mix = c * share + b * (1 - share);
  // 196,608 stratified samples: the noise is far below 1%; tessellation is in [e_lo, e_hi].
  EXPECT_GT(mean, b * e_lo * mix * 0.99);
  EXPECT_LT(mean, b * e_hi * mix * 1.01);
  // What uniform hemisphere sampling would see from the bottom (the cap's solid angle share) is far off.
  const double solid_angle_share = (1 - std::cos(std::atan2(std::sqrt(0.75), 1.5)));
  EXPECT_GT(std::abs(b * e_lo * (c * solid_angle_share + b * (1 - solid_angle_share)) - mean), 0.03 * mean);
}

SceneInputs cornell() {
  SceneInputArgs a;
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  a.scene = dir + "cornell.gltf";
  a.lights = dir + "lights.json";
  a.camera = dir + "camera.json";
  return loadSceneInputs(a);
}

double rmse(const IndirectImage& x, const IndirectImage& y) {
  double s = 0;
  for (std::size_t i = 0; i < x.rgba.size(); ++i) s += (x.rgba[i] - y.rgba[i]) * (x.rgba[i] - y.rgba[i]);
  return std::sqrt(s / double(x.rgba.size()));
}

TEST(ReferenceIndirect, ConvergesWithTheSampleCount) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const SceneInputs in = cornell();
  const Camera& cam = in.cameras.frames.front();
  const IndirectImage truth = traceIndirectReference(in.scene, in.lights, cam, 40, 30, {1024, seed + 1, false});
  double previous = 1e30;
  std::vector<double> errors;
  for (unsigned n : {4u, 16u, 64u, 256u}) {
    const double e = rmse(traceIndirectReference(in.scene, in.lights, cam, 40, 30, {n, seed, false}), truth);
    errors.push_back(e);
    EXPECT_LT(e, previous) << n << " samples";
    previous = e;
  }
  // At least the 1/sqrt(N) rate of plain Monte Carlo over 64x more samples.
  EXPECT_LT(errors[3], errors[0] / 6.0);
  std::printf("rmse vs 1024 samples: 4: %.5f 16: %.5f 64: %.5f 256: %.5f\n", errors[0], errors[1], errors[2], errors[3]);
}

TEST(ReferenceIndirect, ShadowRaysOnlyRemoveLight) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const SceneInputs in = cornell();
  const Camera& cam = in.cameras.frames.front();
  const IndirectImage open = traceIndirectReference(in.scene, in.lights, cam, 40, 30, {16, seed, false});
  const IndirectImage shadowed = traceIndirectReference(in.scene, in.lights, cam, 40, 30, {16, seed, true});
  double sum_open = 0, sum_shadowed = 0;
  for (std::size_t i = 0; i < open.rgba.size(); ++i) {
    ASSERT_LE(shadowed.rgba[i], open.rgba[i] * (1 + 1e-6f) + 1e-9f) << "value " << i;
    sum_open += open.rgba[i];
    sum_shadowed += shadowed.rgba[i];
  }
  EXPECT_LT(sum_shadowed, 0.99 * sum_open);  // the blocks shadow the floor
  EXPECT_GT(sum_shadowed, 0.0);
}

// The reference's camera rays hit where the GL renderer's pixels are covered.
TEST(ReferenceIndirect, SeesWhatTheRendererSees) {
  test::glContext();
  const SceneInputs in = cornell();
  const Camera& cam = in.cameras.frames.front();
  constexpr unsigned kW = 64, kH = 36;
  FrameRenderer renderer(test::runtime(), in.scene, kW, kH);
  renderer.setLights(in.lights);
  BruteForceAssigner brute;
  renderer.render(cam, brute, {Pipeline::Forward, false});
  const std::vector<float> depth = renderer.targets().readDepth(false);
  const IndirectImage img = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {1, 1, false});
  std::size_t differ = 0, covered = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    covered += !gpu::is_sky_depth(depth[i]);
    differ += (img.rgba[4 * i + 3] > 0) != !gpu::is_sky_depth(depth[i]);
  }
  EXPECT_GT(covered, depth.size() / 2);
  EXPECT_LT(covered, depth.size());  // the box does not fill the frame: edges show
  EXPECT_LE(differ, depth.size() / 100) << "silhouettes only";
}

TEST(ReferenceIndirect, RenderCommandWritesTheImagesAndChecksItsFlags) {
  test::TempDir tmp;
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  const std::vector<std::string> base = {"render", "--scene", dir + "cornell.gltf", "--lights", dir + "lights.json",
                                         "--camera", dir + "camera.json", "--size", "32x18", "--frames", "1",
                                         "--warmup", "0"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return test::runCliInProcess(args);
  };
  // The frame renders in a separate process (a render in this one would end the
  // tests' shared GL context); the refused flags never get that far.
  const std::string out = tmp.file("frame.png"), stats = tmp.file("stats.json");
  std::string args;
  for (const auto& a : base) args += a + " ";
  const auto ok = test::runManylights(args + "--gi reference --gi-samples 4 --out " + out + " --stats-json " + stats);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  unsigned w = 0, h = 0;
  const std::vector<float> exr = readImageRgba(tmp.file("frame_gi_reference.exr"), w, h);
  EXPECT_EQ(w, 32u);
  EXPECT_EQ(h, 18u);
  EXPECT_TRUE(std::filesystem::exists(tmp.file("frame_gi_reference.png")));
  float max = 0;
  for (float v : exr) max = std::max(max, v);
  EXPECT_GT(max, 0.0f);
  const auto j = nlohmann::json::parse(std::ifstream(stats));
  EXPECT_EQ(j.at("gi").get<std::string>(), "reference");
  EXPECT_GT(j.at("gi_reference_ms").get<double>(), 0.0);
  EXPECT_EQ(j.at("gi_bounces").get<unsigned>(), 1u);
  for (const auto& bad : std::vector<std::vector<std::string>>{
           {"--gi", "vct-someday"},
           {"--gi", "reference", "--gi-samples", "0"},
           {"--gi-shadows", "maybe"},
           {"--gi", "reference", "--gi-bounces", "0"},
           {"--gi", "reference", "--gi-bounces", "9"},
           {"--gi", "vct", "--gi-reference", "--gi-bounces", "3"}}) {
    const auto r = with(bad);
    EXPECT_EQ(r.exit_code, 2) << bad[0] << " " << bad[1];
    EXPECT_NE(r.err.find(bad[bad.size() - 2]), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST(ReferenceIndirect, RelativeRmseOverCommonlyCoveredPixels) {
  // Pixel 0: both covered, off by (0.1, -0.2, 0) against (1, 2, 0); pixel 1:
  // covered in the image only (a silhouette: counted, not compared); pixel 2:
  // sky in both.
  const std::vector<float> ref = {1, 2, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<float> img = {1.1f, 1.8f, 0, 1, 9, 9, 9, 1, 0, 0, 0, 0};
  const IndirectError e = indirectRelRmse(img, ref);
  EXPECT_EQ(e.pixels, 1u);
  EXPECT_EQ(e.mismatched, 1u);
  EXPECT_NEAR(e.rel_rmse, std::sqrt((0.01 + 0.04) / 5.0), 1e-6);
  EXPECT_EQ(indirectRelRmse(ref, ref).rel_rmse, 0.0);
  EXPECT_EQ(indirectRelRmse(img, std::vector<float>(12, 0.0f)).rel_rmse, -1.0);  // nothing covered
  EXPECT_THROW(indirectRelRmse(img, std::vector<float>(8, 1.0f)), std::invalid_argument);
}

}  // namespace
}  // namespace ml
