// vct::VoxelViewPass (gl/shaders/vct/voxel_view.comp, the voxel volume seen from
// the camera as cubes) against its C++ twin voxelViewPixelTwin, run on the
// volume read back after a VctPipeline update: the Cornell box and random
// triangle soups (fresh seed), random lights, a random camera (outside the
// grid or inside it), a random level, every view kind, odd image sizes. The
// pass poisons its image (NaN) before the dispatch, so a skipped pixel fails.
// Tolerance: each pixel within 1e-5 relative + 1e-6 absolute (GL's division
// need not round correctly), except at most 1% of the pixels + 1: there a ray
// grazes a voxel face or edge and rounding in the DDA's comparisons (fused
// multiply-adds in the shader, not in the twin) sends it into the neighbour.
// Slices (renderSlice) against voxelSlicePixelTwin on the same volumes,
// isotropic and anisotropic, a random level, axis and plane (through a filled
// voxel, or at the ends 0 and 1), every kind, odd image sizes: no pixel off
// by more than 1e-5 relative + 1e-6 (the pixel -> voxel mapping is integer,
// so no grazing allowance). parseVoxelSlice on good and bad text.
// And `render --voxel-view`: its files, one-line errors (exit 2) for a bad
// view name, a level beyond --levels, a bad slice, and the flags without
// --gi vct.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "gl/SceneGpu.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/util/Error.hpp"
#include "host/util/ImageIO.hpp"
#include "host/vct/VctPipeline.hpp"
#include "host/vct/VoxelSlice.hpp"
#include "host/vct/VoxelViewTwin.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/RandomSoup.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"
#include "support/SharedBufferIo.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;
using test::downloadAll;
using test::uniformIn;

const std::string kCornellDir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";

// The volume read back to the host, as the twins take it.
struct ReadBack {
  std::vector<F4> radiance, aniso;  // aniso: empty when isotropic
  std::vector<gpu::VoxelAccum> accum;
};
ReadBack readBack(const VoxelVolume& v) {
  const VoxelGridSettings& s = v.settings();
  ReadBack r;
  r.radiance = downloadAll<F4>(v.radiance(), radianceBytes(s) / sizeof(F4));
  r.accum = downloadAll<gpu::VoxelAccum>(v.accum(), std::size_t(s.voxels) * s.voxels * s.voxels);
  if (s.anisotropic) r.aniso = downloadAll<F4>(*v.anisotropic(), anisotropicBytes(s) / sizeof(F4));
  return r;
}

constexpr VoxelViewKind kKinds[] = {VoxelViewKind::Albedo, VoxelViewKind::Radiance, VoxelViewKind::Opacity};

// The grid's cube.
Aabb gridBounds(const gpu::VoxelGridParams& g) {
  const glm::vec3 o(g.origin_voxel_size.x, g.origin_voxel_size.y, g.origin_voxel_size.z);
  return {o, o + glm::vec3(g.origin_voxel_size.w * float(g.edge))};
}

// Around the grid `b`: a third of the cameras inside it (when `inside` is
// allowed), the rest outside, all looking at points near its centre.
VoxelViewCamera randomCamera(std::mt19937_64& rng, const Aabb& b, bool inside) {
  const glm::vec3 c = 0.5f * (b.min + b.max);
  const float r = 0.5f * glm::length(b.max - b.min);
  auto offset = [&](float s) { return s * glm::vec3(uniformIn(rng, -1, 1), uniformIn(rng, -1, 1), uniformIn(rng, -1, 1)); };
  Camera cam;
  if (rng() % 3 == 0 && inside) {
    cam.eye = c + offset(0.3f * r);
  } else {
    glm::vec3 dir = offset(1.0f);
    if (glm::length(dir) < 1e-3f) dir = glm::vec3(0, 0, 1);
    cam.eye = c + glm::normalize(dir) * r * uniformIn(rng, 1.2f, 3.0f);
  }
  cam.center = c + offset(0.3f * r);
  cam.fovy_degrees = uniformIn(rng, 30, 75);
  cam.near_plane = 0.01f * r;
  cam.far_plane = 100.0f * r;
  const unsigned w = 17 + unsigned(rng() % 64), h = 9 + unsigned(rng() % 48);
  return {cam.view(), cam.projection(float(w) / float(h)), w, h};
}

bool close(float got, float want) {
  return std::isfinite(got) && std::fabs(got - want) <= 1e-5f * std::fabs(want) + 1e-6f;
}

// Renders every view kind of `level` and compares each pixel with the twin.
void checkAgainstTwin(VctPipeline& p, unsigned level, const VoxelViewCamera& cam) {
  const VoxelVolume& v = p.volume();
  const ReadBack host = readBack(v);
  VoxelViewPass pass;
  for (VoxelViewKind kind : kKinds) {
    SCOPED_TRACE(std::string("view ") + voxelViewName(kind) + " level " + std::to_string(level) + " size " +
                 std::to_string(cam.width) + "x" + std::to_string(cam.height));
    const std::vector<float> got = pass.render(v, kind, level, cam);
    std::size_t bad = 0, hits = 0;
    std::string first;
    for (unsigned y = 0; y < cam.height; ++y)
      for (unsigned x = 0; x < cam.width; ++x) {
        const glm::vec4 want = voxelViewPixelTwin(host.radiance, host.accum, v.params(), kind, level, cam, x, y);
        const float* g = &got[4 * (std::size_t(y) * cam.width + x)];
        hits += want.w > 0;
        if (close(g[0], want.x) && close(g[1], want.y) && close(g[2], want.z) && close(g[3], want.w)) continue;
        if (++bad == 1)
          first = "pixel " + std::to_string(x) + "," + std::to_string(y) + ": got " + std::to_string(g[0]) + " " +
                  std::to_string(g[1]) + " " + std::to_string(g[2]) + " " + std::to_string(g[3]) + ", want " +
                  std::to_string(want.x) + " " + std::to_string(want.y) + " " + std::to_string(want.z) + " " +
                  std::to_string(want.w);
      }
    const std::size_t pixels = std::size_t(cam.width) * cam.height;
    std::printf("voxel view %s, level %u, %ux%u: %zu pixels see a voxel, %zu differ from the twin\n",
                voxelViewName(kind), level, cam.width, cam.height, hits, bad);
    EXPECT_LE(bad, pixels / 100 + 1) << bad << " of " << pixels << " pixels differ; first " << first;
    EXPECT_GT(hits, 0u) << "the camera sees no voxel: the comparison would prove nothing";
  }
}

TEST(VctVoxelView, CornellBoxEqualsTheTwin) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const Scene scene = loadGltfScene(kCornellDir + "cornell.gltf");
  const auto lights = loadLightsJson(kCornellDir + "lights.json");
  SceneGpu gpu_scene(scene);
  const unsigned levels = 1 + unsigned(rng() % 5);
  VctPipelineOptions o;
  o.grid = {32, levels, rng() % 2 == 0};
  VctPipeline p(test::runtime(), o, scene.bounds);
  PassTimings t;
  p.update(gpu_scene, lights, t);
  const unsigned level = unsigned(rng() % levels);
  checkAgainstTwin(p, level, randomCamera(rng, gridBounds(p.volume().params()), (32u >> level) >= 4));
}

TEST(VctVoxelView, RandomSoupsEqualTheTwin) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const unsigned edges[] = {1, 2, 4, 8, 16, 32};
  const unsigned edge = edges[rng() % 6];
  const unsigned levels = 1 + unsigned(rng() % (log2Exact(edge) + 1));
  SCOPED_TRACE("edge " + std::to_string(edge) + " levels " + std::to_string(levels));
  const Scene scene = test::randomSoup(rng, 20 + rng() % 40);
  SceneGpu gpu_scene(scene);
  VctPipelineOptions o;
  o.grid = {edge, levels, false};
  VctPipeline p(test::runtime(), o, scene.bounds);
  PassTimings t;
  p.update(gpu_scene, test::randomLightsIn(rng, 1 + rng() % 30, scene.bounds), t);
  // An eye inside a grid of 1-2 voxels per axis passes over its own voxel and may see none.
  const unsigned level = unsigned(rng() % levels);
  checkAgainstTwin(p, level, randomCamera(rng, gridBounds(p.volume().params()), (edge >> level) >= 4));
}

// A plane of `level` through a random filled voxel (opacity > 0), or at an
// end of the grid one time in four; z:0.5 when the level is empty.
VoxelSlice randomSlice(std::mt19937_64& rng, const std::vector<F4>& radiance, unsigned edge, unsigned level) {
  VoxelSlice s;
  s.axis = unsigned(rng() % 3);
  const unsigned e = edge >> level;
  if (rng() % 4 == 0) {
    s.position = rng() % 2 ? 1.0f : 0.0f;
    return s;
  }
  std::vector<unsigned> filled;
  const std::size_t first = gpu::voxel_level_offset(edge, level);
  for (unsigned i = 0; i < e * e * e; ++i)
    if (radiance[first + i].w > 0) filled.push_back(i);
  if (filled.empty()) return s;
  const unsigned i = filled[rng() % filled.size()];
  const unsigned c[3] = {i % e, i / e % e, i / e / e};
  s.position = (float(c[s.axis]) + uniformIn(rng, 0.05f, 0.95f)) / float(e);
  return s;
}

// Every kind of one slice against the twin; returns the pixels that show a voxel.
std::size_t checkSliceAgainstTwin(VctPipeline& p, unsigned level, const VoxelSlice& slice, unsigned w, unsigned h) {
  const VoxelVolume& v = p.volume();
  const ReadBack host = readBack(v);
  VoxelViewPass pass;
  std::size_t hits = 0;
  for (VoxelViewKind kind : kKinds) {
    SCOPED_TRACE(std::string("slice ") + voxelSliceText(slice) + " view " + voxelViewName(kind) + " level " +
                 std::to_string(level) + " size " + std::to_string(w) + "x" + std::to_string(h));
    const std::vector<float> got = pass.renderSlice(v, kind, level, slice, w, h);
    std::size_t bad = 0;
    for (unsigned y = 0; y < h; ++y)
      for (unsigned x = 0; x < w; ++x) {
        const glm::vec4 want =
            voxelSlicePixelTwin(host.radiance, host.aniso, host.accum, v.params(), kind, level, slice, w, h, x, y);
        const float* g = &got[4 * (std::size_t(y) * w + x)];
        hits += want.w > 0;
        if (close(g[0], want.x) && close(g[1], want.y) && close(g[2], want.z) && close(g[3], want.w)) continue;
        if (++bad == 1)
          ADD_FAILURE() << "pixel " << x << "," << y << ": got " << g[0] << " " << g[1] << " " << g[2] << " " << g[3]
                        << ", want " << want.x << " " << want.y << " " << want.z << " " << want.w;
      }
    EXPECT_EQ(bad, 0u) << bad << " of " << std::size_t(w) * h << " pixels differ from the twin";
  }
  std::printf("voxel slice %s, level %u, %ux%u%s: %zu pixels (3 kinds) show a voxel\n", voxelSliceText(slice).c_str(),
              level, w, h, v.settings().anisotropic ? ", anisotropic" : "", hits);
  return hits;
}

TEST(VctVoxelView, SlicesEqualTheTwin) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const unsigned edges[] = {1, 2, 4, 8, 16, 32};
  const unsigned edge = edges[rng() % 6];
  const unsigned levels = 1 + unsigned(rng() % (log2Exact(edge) + 1));
  const bool aniso = levels > 1 && rng() % 2 == 0;
  const bool cornell = rng() % 3 == 0;
  SCOPED_TRACE("edge " + std::to_string(edge) + " levels " + std::to_string(levels) + " anisotropic " +
               std::to_string(aniso) + (cornell ? " cornell" : " soup"));
  const Scene scene = cornell ? loadGltfScene(kCornellDir + "cornell.gltf") : test::randomSoup(rng, 20 + rng() % 40);
  SceneGpu gpu_scene(scene);
  VctPipelineOptions o;
  o.grid = {edge, levels, aniso};
  VctPipeline p(test::runtime(), o, scene.bounds);
  PassTimings t;
  p.update(gpu_scene, test::randomLightsIn(rng, 1 + rng() % 30, scene.bounds), t);
  const std::vector<F4> radiance = readBack(p.volume()).radiance;
  std::size_t hits = 0;
  for (int round = 0; round < 3; ++round) {
    const unsigned level = unsigned(rng() % levels);
    const unsigned w = 1 + unsigned(rng() % 70), h = 1 + unsigned(rng() % 50);
    hits += checkSliceAgainstTwin(p, level, randomSlice(rng, radiance, edge, level), w, h);
  }
  EXPECT_GT(hits, 0u) << "no slice showed a voxel: the comparison would prove nothing";
}

TEST(VctVoxelView, ParsesSlices) {
  const VoxelSlice a = parseVoxelSlice("x", "--voxel-slice");
  EXPECT_EQ(a.axis, 0u);
  EXPECT_EQ(a.position, 0.5f);
  const VoxelSlice b = parseVoxelSlice("y:0", "--voxel-slice");
  EXPECT_EQ(b.axis, 1u);
  EXPECT_EQ(b.position, 0.0f);
  const VoxelSlice c = parseVoxelSlice("z:1", "--voxel-slice");
  EXPECT_EQ(c.axis, 2u);
  EXPECT_EQ(c.position, 1.0f);
  EXPECT_EQ(voxelSliceText(parseVoxelSlice("z:0.25", "f")), "z:0.25");
  for (const char* bad : {"", "w", "X", "xy", "x:", "x:1.5", "x:-0.1", "x:nan", "x:0.5z", "x:0.5:1", ":0.5", "x 0.5"})
    EXPECT_THROW(parseVoxelSlice(bad, "--voxel-slice"), UserError) << "'" << bad << "'";
  // The plane's layer: floor(position * e), the far end in the last layer.
  EXPECT_EQ(voxelSlicePlane({2, 0.0f}, 8), 0u);
  EXPECT_EQ(voxelSlicePlane({2, 0.5f}, 8), 4u);
  EXPECT_EQ(voxelSlicePlane({2, 0.99f}, 8), 7u);
  EXPECT_EQ(voxelSlicePlane({2, 1.0f}, 8), 7u);
  EXPECT_EQ(voxelSlicePlane({0, 1.0f}, 1), 0u);
}

TEST(VctVoxelView, RejectsABadLevelOnTheDevicePath) {
  test::glContext();
  VctPipelineOptions o;
  o.grid = {8, 2, false};
  VctPipeline p(test::runtime(), o, Aabb{glm::vec3(-1), glm::vec3(1)});
  VoxelViewPass pass;
  EXPECT_THROW(pass.render(p.volume(), VoxelViewKind::Opacity, 2, {glm::mat4(1), glm::mat4(1), 4, 4}), UserError);
}

std::size_t lineCount(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n')) + (!s.empty() && s.back() != '\n');
}

void expectUsageError(const test::CommandResult& r, const std::string& must_mention) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(must_mention), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1u) << r.err;
}

TEST(VctVoxelView, RenderCommandBadFlagsAreOneLineExit2) {
  const std::string vct = "render --size 16x16 --gi vct --voxels 16 --levels 3 ";
  expectUsageError(test::runManylights(vct + "--voxel-view colour"), "--voxel-view");
  expectUsageError(test::runManylights(vct + "--voxel-view albedo --voxel-level 3"), "--voxel-level");
  expectUsageError(test::runManylights("render --size 16x16 --voxel-view opacity"), "--voxel-view");
  expectUsageError(test::runManylights(vct + "--voxel-level 1"), "--voxel-level");
  expectUsageError(test::runManylights(vct + "--voxel-view opacity"), "--out");
  expectUsageError(test::runManylights(vct + "--voxel-view opacity --voxel-slice w"), "--voxel-slice");
  expectUsageError(test::runManylights(vct + "--voxel-view opacity --voxel-slice z:1.5"), "--voxel-slice");
  expectUsageError(test::runManylights(vct + "--voxel-slice z"), "--voxel-slice");
}

// `render` of the Cornell box at 64x48 with VCT (32^3 x 3 levels) and `flags`, writing `out`.
test::CommandResult renderCornellVct(const std::string& flags, const std::string& out) {
  return test::runManylights("render --scene " + kCornellDir + "cornell.gltf --lights " + kCornellDir +
                             "lights.json --camera " + kCornellDir + "camera.json --size 64x48 --frames 1 "
                             "--warmup 0 --gi vct --voxels 32 --levels 3 " + flags + " --out " + out);
}

TEST(VctVoxelView, RenderCommandWritesTheView) {
  test::TempDir tmp;
  const std::string out = tmp.file("f.png");
  const auto r = renderCornellVct("--voxel-view radiance --voxel-level 1", out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(tmp.file("f_gi_vct_voxels.png")));
  unsigned w = 0, h = 0;
  const auto exr = readImageRgba(tmp.file("f_gi_vct_voxels.exr"), w, h);
  ASSERT_EQ(w, 64u);
  ASSERT_EQ(h, 48u);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < exr.size(); i += 4) {
    ASSERT_TRUE(exr[i + 3] == 0.0f || exr[i + 3] == 1.0f) << "alpha " << exr[i + 3];
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(exr[i + c]));
    hits += exr[i + 3] == 1.0f;
  }
  EXPECT_GT(hits, exr.size() / 4 / 2) << "the Cornell camera looks into the box: most pixels see a voxel";
}

TEST(VctVoxelView, RenderCommandWritesTheSlice) {
  test::TempDir tmp;
  const std::string out = tmp.file("f.png");
  const auto r = renderCornellVct("--anisotropic --voxel-view opacity --voxel-level 1 --voxel-slice z:0.1", out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(tmp.file("f_gi_vct_slice.png")));
  EXPECT_FALSE(std::filesystem::exists(tmp.file("f_gi_vct_voxels.png"))) << "the slice replaces the cubes";
  unsigned w = 0, h = 0;
  const auto exr = readImageRgba(tmp.file("f_gi_vct_slice.exr"), w, h);
  ASSERT_EQ(w, 64u);
  ASSERT_EQ(h, 48u);
  // The back wall's layer (z in [-1.1, -1] of a grid from about -1.1): the
  // 48x48 square in the middle is the plane, the 8-pixel bands beside it empty.
  std::size_t hits = 0;
  for (unsigned y = 0; y < h; ++y)
    for (unsigned x = 0; x < w; ++x) {
      const float a = exr[4 * (std::size_t(y) * w + x) + 3];
      if (x < 8 || x >= 56) {
        EXPECT_EQ(a, 0.0f) << x << "," << y;
      }
      hits += a == 1.0f;
    }
  EXPECT_GT(hits, 48u * 48u / 2) << "the back wall fills most of the plane";
}

}  // namespace
}  // namespace ml::vct
