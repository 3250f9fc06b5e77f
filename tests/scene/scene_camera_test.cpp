// Camera matrices (checked against glm and against hand-derived projections),
// CameraParams layout, JSON load/save (manylights and nTiled formats), errors,
// and the shipped default camera path.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "host/scene/Camera.hpp"
#include "host/util/Error.hpp"
#include "support/FileErrors.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"

namespace {

namespace fs = std::filesystem;

using ml::test::TempDir;

ml::Camera randomCamera(std::mt19937_64& rng) {
  std::uniform_real_distribution<float> coord(-50.0f, 50.0f), fov(20.0f, 110.0f), nearp(0.01f, 1.0f);
  ml::Camera c;
  c.eye = {coord(rng), coord(rng), coord(rng)};
  do c.center = {coord(rng), coord(rng), coord(rng)};
  while (glm::length(c.center - c.eye) < 1.0f);
  c.up = glm::normalize(glm::vec3(coord(rng), 50.0f, coord(rng)));
  c.fovy_degrees = fov(rng);
  c.near_plane = nearp(rng);
  c.far_plane = c.near_plane * 1000.0f;
  return c;
}

glm::vec3 ndc(const ml::Camera& c, float aspect, glm::vec3 world) {
  const glm::vec4 clip = c.projection(aspect) * c.view() * glm::vec4(world, 1.0f);
  return glm::vec3(clip) / clip.w;
}

TEST(CameraMatrices, MatchGlmLookAtAndPerspective) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 50; ++i) {
    const ml::Camera c = randomCamera(rng);
    const float aspect = 0.5f + float(i) / 10.0f;
    const glm::mat4 v = c.view(), ref_v = glm::lookAt(c.eye, c.center, c.up);
    // Reversed-Z into [0, 1] is glm's zero-to-one perspective with near and far swapped.
    const glm::mat4 p = c.projection(aspect),
                    ref_p = glm::perspectiveRH_ZO(glm::radians(c.fovy_degrees), aspect, c.far_plane, c.near_plane);
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) {
        EXPECT_NEAR(v[col][row], ref_v[col][row], 1e-5f);
        EXPECT_NEAR(p[col][row], ref_p[col][row], 1e-5f * std::abs(ref_p[col][row]) + 1e-6f);
      }
  }
}

TEST(CameraMatrices, ViewPutsEyeAtOriginLookingDownMinusZ) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 50; ++i) {
    const ml::Camera c = randomCamera(rng);
    const glm::mat4 v = c.view();
    const float dist = glm::length(c.center - c.eye);
    const glm::vec3 eye_v = glm::vec3(v * glm::vec4(c.eye, 1.0f));
    const glm::vec3 center_v = glm::vec3(v * glm::vec4(c.center, 1.0f));
    EXPECT_NEAR(glm::length(eye_v), 0.0f, 1e-4f);
    EXPECT_NEAR(center_v.x, 0.0f, 1e-4f);
    EXPECT_NEAR(center_v.y, 0.0f, 1e-4f);
    EXPECT_NEAR(center_v.z, -dist, 1e-4f * dist);
    // The up vector ends up in the view's y/z plane, pointing up.
    const glm::vec3 up_v = glm::vec3(v * glm::vec4(c.up, 0.0f));
    EXPECT_NEAR(up_v.x, 0.0f, 1e-5f);
    EXPECT_GT(up_v.y, 0.0f);
    // Rigid: rows of the rotation part are orthonormal (right-handed: det +1).
    EXPECT_NEAR(glm::determinant(glm::mat3(v)), 1.0f, 1e-5f);
  }
}

TEST(CameraMatrices, ProjectionMapsFrustumToGlClipCube) {
  ml::Camera c;
  c.eye = {1, 2, 3};
  c.center = {1, 2, -7};  // looking down -z: view space == world space shifted
  c.up = {0, 1, 0};
  c.fovy_degrees = 90.0f;  // tan(45) = 1: the frustum edge at distance d is at height d
  c.near_plane = 0.5f;
  c.far_plane = 50.0f;
  const float aspect = 2.0f;

  const glm::vec3 centre = ndc(c, aspect, c.center);
  EXPECT_NEAR(centre.x, 0.0f, 1e-6f);
  EXPECT_NEAR(centre.y, 0.0f, 1e-6f);
  EXPECT_GT(centre.z, 0.0f);
  EXPECT_LT(centre.z, 1.0f);

  // Reversed-Z (host/shared/depth_convention.h): near plane -> 1, far plane -> 0.
  EXPECT_NEAR(ndc(c, aspect, {1, 2, 3 - 0.5f}).z, 1.0f, 1e-6f);
  EXPECT_NEAR(ndc(c, aspect, {1, 2, 3 - 50.0f}).z, 0.0f, 1e-7f);
  EXPECT_NEAR(ndc(c, aspect, {1, 2, 3 - 5.0f}).z, 0.5f / 5.0f * (50.0f - 5.0f) / (50.0f - 0.5f), 1e-7f);
  const float d = 4.0f;
  EXPECT_NEAR(ndc(c, aspect, {1, 2 + d, 3 - d}).y, 1.0f, 1e-5f);          // top edge
  EXPECT_NEAR(ndc(c, aspect, {1 + 2 * d, 2, 3 - d}).x, 1.0f, 1e-5f);      // right edge: aspect 2
  EXPECT_NEAR(ndc(c, aspect, {1 - d, 2 - d / 2, 3 - d}).x, -0.5f, 1e-5f);  // left half-way
  EXPECT_NEAR(ndc(c, aspect, {1 - d, 2 - d / 2, 3 - d}).y, -0.5f, 1e-5f);
}

TEST(CameraMatrices, ParamsAreColumnMajorWithLensData) {
  ml::Camera c;
  c.eye = {3, 4, 5};
  c.center = {0, 1, 0};
  c.fovy_degrees = 60.0f;
  c.near_plane = 0.25f;
  c.far_plane = 300.0f;
  const ml::gpu::CameraParams p = c.params(1920, 1080);
  const glm::mat4 v = c.view(), pr = c.projection(1920.0f / 1080.0f);
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      EXPECT_EQ(p.view[col * 4 + row], v[col][row]);
      EXPECT_EQ(p.proj[col * 4 + row], pr[col][row]);
    }
  // Column-major: the view's translation is in elements 12..14 and the
  // perspective's -1 (w = -z_view) sits at row 3, column 2 = element 11.
  EXPECT_NE(p.view[14], 0.0f);
  EXPECT_EQ(p.proj[11], -1.0f);
  EXPECT_GT(p.proj[14], 0.0f);  // reversed-Z: clip z = near f / (f - n) at z_view = 0
  EXPECT_NEAR(p.tan_half_fovy, 1.0f / std::sqrt(3.0f), 1e-6f);  // tan(30 deg)
  EXPECT_FLOAT_EQ(p.aspect, 16.0f / 9.0f);
  EXPECT_EQ(p.near_plane, 0.25f);
  EXPECT_EQ(p.far_plane, 300.0f);
  EXPECT_EQ(p.width, 1920u);
  EXPECT_EQ(p.height, 1080u);
  const ml::gpu::CameraParams z = c.params(0, 0);  // minimised window: finite numbers
  for (float f : z.proj) EXPECT_TRUE(std::isfinite(f));
}

void expectSame(const ml::Camera& a, const ml::Camera& b) {
  EXPECT_EQ(a.eye, b.eye);
  EXPECT_EQ(a.center, b.center);
  EXPECT_EQ(a.up, b.up);
  EXPECT_EQ(a.fovy_degrees, b.fovy_degrees);
  EXPECT_EQ(a.near_plane, b.near_plane);
  EXPECT_EQ(a.far_plane, b.far_plane);
}

TEST(CameraJson, RoundTripSingleAndPath) {
  const std::uint64_t seed = ml::test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  TempDir dir;

  ml::CameraPath single;
  single.frames.push_back(randomCamera(rng));
  ml::saveCameraJson(dir.file("single.json"), single);
  const ml::CameraPath s = ml::loadCameraJson(dir.file("single.json"));
  ASSERT_EQ(s.frames.size(), 1u);
  expectSame(s.frames[0], single.frames[0]);

  ml::CameraPath path;
  for (int i = 0; i < 40; ++i) {
    path.frames.push_back(randomCamera(rng));
    if (i % 3) {  // most frames share the first frame's lens, some do not
      path.frames.back().fovy_degrees = path.frames[0].fovy_degrees;
      path.frames.back().near_plane = path.frames[0].near_plane;
      path.frames.back().far_plane = path.frames[0].far_plane;
    }
  }
  ml::saveCameraJson(dir.file("path.json"), path);
  const ml::CameraPath loaded = ml::loadCameraJson(dir.file("path.json"));
  ASSERT_EQ(loaded.frames.size(), path.frames.size());
  for (std::size_t i = 0; i < path.frames.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    expectSame(loaded.frames[i], path.frames[i]);
  }
}

TEST(CameraJson, HandWrittenSingleCameraAndPathDefaults) {
  TempDir dir;
  const ml::CameraPath one = ml::loadCameraJson(dir.write(
      "one.json", R"({"eye": [1, 2, 3], "center": [4, 5, 6], "up": [0, 0, 1], "fovy": 70, "near": 0.5, "far": 90})"));
  ASSERT_EQ(one.frames.size(), 1u);
  EXPECT_EQ(one.frames[0].eye, glm::vec3(1, 2, 3));
  EXPECT_EQ(one.frames[0].center, glm::vec3(4, 5, 6));
  EXPECT_EQ(one.frames[0].up, glm::vec3(0, 0, 1));
  EXPECT_EQ(one.frames[0].fovy_degrees, 70.0f);
  EXPECT_EQ(one.frames[0].near_plane, 0.5f);
  EXPECT_EQ(one.frames[0].far_plane, 90.0f);

  // Path-level lens applies to every frame unless a frame overrides it; up defaults to +y.
  const ml::CameraPath path = ml::loadCameraJson(dir.write("path.json", R"({"fovy": 50, "near": 0.2, "far": 80,
      "frames": [{"eye": [0, 0, 5], "center": [0, 0, 0]}, {"eye": [0, 0, 4], "center": [0, 0, 0], "fovy": 30}]})"));
  ASSERT_EQ(path.frames.size(), 2u);
  EXPECT_EQ(path.frames[0].up, glm::vec3(0, 1, 0));
  EXPECT_EQ(path.frames[0].fovy_degrees, 50.0f);
  EXPECT_EQ(path.frames[1].fovy_degrees, 30.0f);
  EXPECT_EQ(path.frames[1].near_plane, 0.2f);
  EXPECT_EQ(path.frames[1].far_plane, 80.0f);
}

TEST(CameraJson, LoadsNTiledCameraFormat) {
  // Shape of the nTiled suite's camera.json: frames of object vectors, an up
  // vector that is neither unit length nor exactly perpendicular, no lens fields.
  TempDir dir;
  const std::string path = dir.write("camera.json", R"({
  "frames": [
    {
      "center": {"x": -0.05737307667732239, "y": 8.694186210632324, "z": 96.63692474365234},
      "eye": {"x": -0.057373080402612686, "y": 8.694186210632324, "z": 99.63693237304688},
      "up": {"x": 3.725290298461914e-09, "y": 2.4472265243530273, "z": -7.62939453125e-06}
    },
    {
      "center": {"x": -0.057373084127902985, "y": 8.69418716430664, "z": 96.59491729736328},
      "eye": {"x": -0.057373080402612686, "y": 8.694186210632324, "z": 99.59491729736328},
      "up": {"x": -3.725290298461914e-09, "y": 2.4472265243530273, "z": -0.0}
    }
  ]
})");
  const ml::CameraPath cams = ml::loadCameraJson(path);
  ASSERT_EQ(cams.frames.size(), 2u);
  auto f = [](double d) { return static_cast<float>(d); };  // JSON numbers are doubles, then narrowed
  EXPECT_EQ(cams.frames[0].eye, glm::vec3(f(-0.057373080402612686), f(8.694186210632324), f(99.63693237304688)));
  EXPECT_EQ(cams.frames[1].center, glm::vec3(f(-0.057373084127902985), f(8.69418716430664), f(96.59491729736328)));
  EXPECT_EQ(cams.frames[0].up.y, f(2.4472265243530273));
  EXPECT_EQ(cams.frames[0].fovy_degrees, ml::Camera{}.fovy_degrees);
  // The unnormalised up still gives a proper rotation looking down -z.
  const glm::mat4 v = cams.frames[0].view();
  EXPECT_NEAR(glm::determinant(glm::mat3(v)), 1.0f, 1e-5f);
  EXPECT_NEAR(v[2][2], 1.0f, 1e-5f);  // world +z maps to view +z (camera looks down world -z)
}

void expectCameraError(const std::string& path, const std::string& also) {
  ml::test::expectFileError([&] { (void)ml::loadCameraJson(path); }, path, also);
}

TEST(CameraJson, ErrorsNameFileAndFrame) {
  TempDir dir;
  expectCameraError(dir.file("missing.json"), "cannot open");
  expectCameraError(dir.write("syntax.json", "{\"eye\": [0, 0,\n"), "JSON");
  expectCameraError(dir.write("array.json", "[1, 2]"), "object");
  expectCameraError(dir.write("noframes.json", R"({"frames": []})"), "frames");
  expectCameraError(dir.write("noeye.json", R"({"center": [0, 0, 0]})"), "eye");

  auto frame1 = [&](const std::string& name, const std::string& bad, const std::string& also) {
    SCOPED_TRACE(name);
    const std::string path =
        dir.write(name, R"({"frames": [{"eye": [0, 0, 5], "center": [0, 0, 0]}, )" + bad + "]}");
    expectCameraError(path, "frame 1");
    expectCameraError(path, also);
  };
  frame1("same.json", R"({"eye": [1, 2, 3], "center": [1, 2, 3]})", "coincide");
  frame1("fov0.json", R"({"eye": [0, 0, 5], "center": [0, 0, 0], "fovy": 0})", "fovy");
  frame1("fov180.json", R"({"eye": [0, 0, 5], "center": [0, 0, 0], "fovy": 180})", "fovy");
  frame1("near0.json", R"({"eye": [0, 0, 5], "center": [0, 0, 0], "near": 0})", "near");
  frame1("farnear.json", R"({"eye": [0, 0, 5], "center": [0, 0, 0], "near": 2, "far": 2})", "far");
  frame1("upparallel.json", R"({"eye": [0, 5, 0], "center": [0, 0, 0], "up": [0, 2, 0]})", "parallel");
  frame1("upzero.json", R"({"eye": [0, 0, 5], "center": [0, 0, 0], "up": [0, 0, 0]})", "up");
  frame1("eye2.json", R"({"eye": [0, 5], "center": [0, 0, 0]})", "eye");
  frame1("center_str.json", R"({"eye": [0, 0, 5], "center": "origin"})", "center");
  frame1("eye_huge.json", R"({"eye": [0, 1e39, 5], "center": [0, 0, 0]})", "finite");  // beyond float range
  // Beyond double range: nlohmann refuses the number itself.
  expectCameraError(dir.write("overflow.json", R"({"eye": [0, 1e999, 5], "center": [0, 0, 0]})"), "JSON");

  // Path-level lens errors are reported for the first frame that uses them.
  expectCameraError(dir.write("pathfov.json", R"({"fovy": -10, "frames": [{"eye": [0, 0, 5], "center": [0, 0, 0]}]})"),
                    "fovy");
}

TEST(CameraDefault, ShippedPathIsShortAndSmooth) {
  const ml::CameraPath cams = ml::loadCameraJson(std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/camera.json");
  EXPECT_GE(cams.frames.size(), 30u);
  EXPECT_LE(cams.frames.size(), 120u);
  for (std::size_t i = 1; i < cams.frames.size(); ++i) {
    EXPECT_LT(glm::length(cams.frames[i].eye - cams.frames[i - 1].eye), 2.0f) << "frame " << i;
    const glm::vec3 d0 = glm::normalize(cams.frames[i - 1].center - cams.frames[i - 1].eye);
    const glm::vec3 d1 = glm::normalize(cams.frames[i].center - cams.frames[i].eye);
    EXPECT_GT(glm::dot(d0, d1), std::cos(glm::radians(20.0f))) << "frame " << i;
  }
}

}  // namespace
