// The thesis scene-suite loader on a suite the test writes itself: world
// positions after nTiled's translation/rotation convention, normals, mesh
// lookup from Windows paths, camera settings, light-file ordering, and the
// missing-mesh error / --allow-missing-meshes behaviour.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "host/suite/NtiledSuite.hpp"
#include "host/util/Error.hpp"
#include "suite_support.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

constexpr float kHalfPi = std::numbers::pi_v<float> / 2;

// Independent of the loader: the rotations written out by hand.
glm::vec3 rotX(glm::vec3 v, float a) {
  return {v.x, std::cos(a) * v.y - std::sin(a) * v.z, std::sin(a) * v.y + std::cos(a) * v.z};
}
glm::vec3 rotY(glm::vec3 v, float a) {
  return {std::cos(a) * v.x + std::sin(a) * v.z, v.y, -std::sin(a) * v.x + std::cos(a) * v.z};
}
glm::vec3 rotZ(glm::vec3 v, float a) {
  return {std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z};
}

bool hasVertexNear(const Scene& s, glm::vec3 p, glm::vec3* normal = nullptr) {
  for (const auto& v : s.vertices)
    if (glm::length(v.position - p) < 1e-4f) {
      if (normal) *normal = v.normal;
      return true;
    }
  return false;
}

std::string suiteDir() {
  static const std::string dir = test::writeSmallSuite(test::tempDir() + "/suites", "small-scene", false);
  return dir;
}

TEST(SuiteLoader, TransformIsTranslateTimesRxRyRz) {
  const glm::vec3 t(1, 2, 3), r(0.3f, -0.7f, 1.1f), v(0.5f, -2.0f, 4.0f);
  const glm::vec3 expected = t + rotX(rotY(rotZ(v, r.z), r.y), r.x);
  const glm::vec3 got = glm::vec3(ntiledObjectTransform(t, r) * glm::vec4(v, 1.0f));
  EXPECT_LT(glm::length(got - expected), 1e-5f) << got.x << " " << got.y << " " << got.z;
}

TEST(SuiteLoader, LoadsObjectsInWorldSpace) {
  const SuiteScene s = loadNtiledSuite(suiteDir());
  EXPECT_EQ(s.name, "small-scene");
  EXPECT_EQ(s.placed_objects, 3u);
  EXPECT_TRUE(s.missing_meshes.empty());
  EXPECT_EQ(s.scene.triangleCount(), 2u + 1u + 1u);
  ASSERT_EQ(s.scene.materials.size(), 1u);
  EXPECT_EQ(s.scene.materials[0].base_color, glm::vec4(1.0f));
  ASSERT_EQ(s.scene.batches.size(), 1u);
  EXPECT_EQ(s.scene.batches[0].index_count, s.scene.indices.size());

  // Wall: translated only; its generated normal faces +z (counter-clockwise quad).
  glm::vec3 n;
  ASSERT_TRUE(hasVertexNear(s.scene, {-10, -10, -10}, &n));
  EXPECT_LT(glm::length(n - glm::vec3(0, 0, 1)), 1e-5f);
  EXPECT_TRUE(hasVertexNear(s.scene, {10, 10, -10}));

  // Tri.0: Ry(pi/2) then +(10,0,0): (1,0,0) -> (10,0,-1); the given normal (0,0,1) -> (1,0,0).
  ASSERT_TRUE(hasVertexNear(s.scene, {10, 0, -1}, &n));
  EXPECT_LT(glm::length(n - glm::vec3(1, 0, 0)), 1e-5f);
  EXPECT_TRUE(hasVertexNear(s.scene, {10, 1, 0}));  // (0,1,0) stays
  EXPECT_TRUE(hasVertexNear(s.scene, {11, 0, 0}));  // (0,0,1) -> (1,0,0)

  // Tri.1: rotation (pi/2, pi/2, 0) = Rx(pi/2) * Ry(pi/2): (1,0,0) -> (0,0,-1) -> (0,1,0);
  // the other order (Ry after Rx) would give (0,0,-1).
  const glm::vec3 expected = glm::vec3(0, 20, 0) + rotX(rotY({1, 0, 0}, kHalfPi), kHalfPi);
  EXPECT_LT(glm::length(expected - glm::vec3(0, 21, 0)), 1e-5f);
  EXPECT_TRUE(hasVertexNear(s.scene, {0, 21, 0}));
  EXPECT_FALSE(hasVertexNear(s.scene, {0, 20, -1}));

  for (const auto& v : s.scene.vertices) EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
  EXPECT_LT(glm::length(s.scene.bounds.min - glm::vec3(-10, -10, -10)), 1e-4f);
  EXPECT_TRUE(hasVertexNear(s.scene, {0, 20, 1}));  // (0,1,0) -> (0,1,0) -> (0,0,1)
  EXPECT_LT(glm::length(s.scene.bounds.max - glm::vec3(11, 21, 1)), 1e-4f);
}

TEST(SuiteLoader, CameraPathGetsTheSuiteLens) {
  SuiteLoadOptions o;
  const SuiteScene s = loadNtiledSuite(suiteDir(), o);
  ASSERT_EQ(s.cameras.frames.size(), 3u);
  for (const Camera& c : s.cameras.frames) {
    EXPECT_EQ(c.fovy_degrees, 45.0f);
    EXPECT_EQ(c.near_plane, 0.01f);
    EXPECT_EQ(c.far_plane, 4000.0f);
    EXPECT_EQ(c.up, glm::vec3(0, 2, 0));  // as written; lookAt normalises
  }
  EXPECT_EQ(s.cameras.frames[2].eye, glm::vec3(0, 0, 2));
  EXPECT_EQ(s.cameras.frames[2].center, glm::vec3(0, 0, -1));
  o.camera.fovy_degrees = 60.0f;
  EXPECT_EQ(loadNtiledSuite(suiteDir(), o).cameras.frames[1].fovy_degrees, 60.0f);
}

TEST(SuiteLoader, LightFilesByCountAndTheThesisSets) {
  const SuiteScene s = loadNtiledSuite(suiteDir());
  ASSERT_EQ(s.light_files.size(), 3u);
  namespace fs = std::filesystem;
  EXPECT_EQ(fs::path(s.light_files[0]).filename(), "10#1x_1y_1z.json");
  EXPECT_EQ(fs::path(s.light_files[1]).filename(), "20#1x_1y_2z.json");
  EXPECT_EQ(fs::path(s.light_files[2]).filename(), "20#2x_1y_1z.json");
  const auto thesis = thesisLightFiles(s.light_files);
  ASSERT_EQ(thesis.size(), 2u);
  EXPECT_EQ(fs::path(thesis[1]).filename(), "20#2x_1y_1z.json");
  EXPECT_EQ(lightCountFromFileName("C:\\x\\1260#3x_3y_2z.json"), 1260u);
  EXPECT_EQ(lightCountFromFileName("lights.json"), 0u);
  EXPECT_EQ(lightCountFromFileName("70.json"), 0u);
}

TEST(SuiteLoader, MissingMeshIsAnErrorUnlessAllowed) {
  const std::string dir = test::writeSmallSuite(test::tempDir() + "/suites", "with-missing", true);
  try {
    loadNtiledSuite(dir);
    FAIL() << "expected a UserError";
  } catch (const UserError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("Gone.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("--allow-missing-meshes"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  SuiteLoadOptions o;
  o.allow_missing_meshes = true;
  const SuiteScene s = loadNtiledSuite(dir, o);
  ASSERT_EQ(s.missing_meshes.size(), 1u);
  EXPECT_EQ(s.missing_meshes[0], "Gone");
  EXPECT_EQ(s.placed_objects, 3u);
  EXPECT_EQ(s.objects.size(), 4u);
  EXPECT_EQ(s.scene.triangleCount(), 4u);
}

TEST(SuiteLoader, MalformedInputNamesTheFile) {
  namespace fs = std::filesystem;
  const std::string dir = test::writeSmallSuite(test::tempDir() + "/suites", "broken", false);
  EXPECT_TRUE(isNtiledSuiteDir(dir));
  EXPECT_FALSE(isNtiledSuiteDir(dir + "/obj"));
  const std::string geo = dir + "/geometry/deferred_attenuated.json";
  test::writeText(geo, "{\"objects\": [ {\"mesh_id\": 3} ]}");
  try {
    loadNtiledSuite(dir);
    FAIL();
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(geo), std::string::npos) << e.what();
  }
  test::writeText(geo, "{\"objects\": [");
  EXPECT_THROW(loadNtiledSuite(dir), UserError);
  fs::remove(geo);
  EXPECT_THROW(loadNtiledSuite(dir), UserError);  // no geometry file at all
  EXPECT_THROW(loadNtiledSuite(dir + "/nope"), UserError);
}

}  // namespace
}  // namespace ml
