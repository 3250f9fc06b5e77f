// The command line as users meet it: bad input gets one clear line naming the
// file or flag and exit code 2; a good render writes its image and JSON.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "host/util/ImageIO.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

using test::lines;
using test::runManylights;

void expectUserError(const test::CommandResult& r, const std::string& must_mention) {
  EXPECT_EQ(r.exit_code, 2) << "stderr: " << r.err;
  EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(must_mention), std::string::npos) << "expected '" << must_mention << "' in: " << r.err;
  EXPECT_EQ(lines(r.err), 1) << "expected one line: " << r.err;
}

std::string writeFile(const std::string& name, const std::string& content) {
  const std::string p = test::tempDir() + "/" + name;
  std::ofstream(p) << content;
  return p;
}

TEST(Cli, MissingScene) { expectUserError(runManylights("render --scene /no/such/scene.glb"), "/no/such/scene.glb"); }

TEST(Cli, MalformedScene) {
  const auto p = writeFile("broken.gltf", "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ {");
  expectUserError(runManylights("render --scene " + p), p);
}

TEST(Cli, BadLightJson) {
  const auto p = writeFile("bad_lights.json", "{\"lights\": [ {\"position\": [1,2], \"radius\": 1} ]}");
  expectUserError(runManylights("render --size 32x32 --lights " + p), p);
  const auto q = writeFile("notjson.json", "this is not json");
  expectUserError(runManylights("render --size 32x32 --lights " + q), q);
}

TEST(Cli, BadCameraJson) {
  const auto p = writeFile("bad_camera.json", "{\"eye\": [0,0,0], \"center\": [0,0,0], \"up\": [0,1,0]}");
  expectUserError(runManylights("render --size 32x32 --camera " + p), p);
}

TEST(Cli, UnknownTechnique) { expectUserError(runManylights("render --technique magic"), "--technique"); }

TEST(Cli, BadKernelShape) {
  expectUserError(runManylights("render --technique tiled-deferred --kernel-shape warp"), "--kernel-shape");
}

TEST(Cli, BadSizes) {
  expectUserError(runManylights("render --size 0x100"), "--size");
  expectUserError(runManylights("render --size -5x100"), "--size");
  expectUserError(runManylights("render --size big"), "--size");
}

TEST(Cli, BadVctFlags) {
  const std::string vct = "render --size 16x16 --gi vct ";
  // Each row: the flags after `vct`, and the flag the one error line must name.
  const std::pair<const char*, const char*> refused[] = {
      {"--voxels 63", "--voxels"},
      {"--voxels 1024", "--voxels"},
      {"--voxels 16 --levels 6", "--levels"},
      {"--cone-aperture 0", "--cone-aperture"},
      {"--cone-aperture 180", "--cone-aperture"},
      {"--cone-lod-bias -0.5", "--cone-lod-bias"},
      {"--cone-lod-bias 5", "--cone-lod-bias"},
      {"--cone-lod-bias fine", "--cone-lod-bias"},
      {"--cones 0", "--cones"},
      {"--cones 33", "--cones"},
      {"--gi-scale 0", "--gi-scale"},
      {"--gi-scale 1.5", "--gi-scale"},
      {"--vct-shadows ray", "--vct-shadows"},
      // The reference must model vct's transport: ray with voxel shadows, else none.
      {"--gi-reference --gi-shadows ray", "--gi-shadows"},
      {"--vct-shadows voxel --gi-reference --gi-shadows none", "--gi-shadows"},
      {"--vct-shadows voxel --gi-shadows bogus", "--gi-shadows"},
      {"--no-shading", "--gi"},
      {"--voxel-view albedo --voxel-slice v", "--voxel-slice"},
      {"--voxel-view albedo --voxel-slice y:-1", "--voxel-slice"},
      {"--voxel-slice x:0.5", "--voxel-slice"},
      {"--vct-cascades 0", "--vct-cascades"},
      {"--vct-cascades 5", "--vct-cascades"},
      // What one grid alone models refuses cascades, naming itself.
      {"--vct-cascades 2 --gi-bounces 2", "--gi-bounces"},
      {"--vct-cascades 2 --vct-shadows voxel", "--vct-shadows"},
      {"--vct-fold", "--vct-fold"},
      {"--vct-cascades 2 --vct-fold=maybe", "--vct-fold"},
  };
  for (const auto& [flags, named] : refused) {
    SCOPED_TRACE(flags);
    expectUserError(runManylights(vct + flags), named);
  }
  expectUserError(runManylights("render --size 16x16 --gi reference --gi-reference"), "--gi-reference");
}

TEST(Cli, BadDevice) {
  expectUserError(runManylights("render --size 16x16 --device 99"), "--device");
  expectUserError(runManylights("render --size 16x16 --device fastest"), "--device");
}

TEST(Cli, NoOpenClPlatformNamesThePackage) {
  const std::string empty = test::tempDir() + "/no-icds";
  std::filesystem::create_directories(empty);
  expectUserError(runManylights("devices", "OCL_ICD_VENDORS=" + empty), "pocl-opencl-icd");
  expectUserError(runManylights("render --size 16x16", "OCL_ICD_VENDORS=" + empty), "pocl-opencl-icd");
}

TEST(Cli, NoEglDisplay) {
  expectUserError(runManylights("render --size 16x16", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json"), "EGL");
}

TEST(Cli, HelpListsEveryRenderFlag) {
  auto r = runManylights("render --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* flag : {"--scene", "--lights", "--technique", "--size", "--camera", "--out", "--device",
                           "--counts", "--stats-json", "--kernel-shape"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
}

TEST(Cli, RenderWritesImageAndStats) {
  const std::string png = test::tempDir() + "/out.png";
  const std::string json = test::tempDir() + "/stats.json";
  auto r = runManylights("render --size 96x64 --lights 200 --technique deferred --frames 2 --out " + png +
                         " --stats-json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  unsigned w = 0, h = 0;
  auto img = readImageRgba(png, w, h);
  EXPECT_EQ(w, 96u);
  EXPECT_EQ(h, 64u);
  std::ifstream in(json);
  auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["technique"], "deferred");
  EXPECT_EQ(j["width"], 96);
  EXPECT_EQ(j["height"], 64);
  EXPECT_EQ(j["lights"], 200);
  ASSERT_TRUE(j["passes"].is_object());
  EXPECT_TRUE(j["passes"].contains("gbuffer"));
  EXPECT_TRUE(j["passes"].contains("deferred-shading"));
  EXPECT_EQ(j["light_evaluations"].get<std::uint64_t>(), 200u * j["covered_pixels"].get<std::uint64_t>());
  EXPECT_LE(j["lower_bound"].get<std::uint64_t>(), j["light_evaluations"].get<std::uint64_t>());
  EXPECT_NE(r.out.find("deferred-shading"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ml
