// Hashed shading's octree-cell debug view (host/hashed/OctreeCellView.hpp):
// LinklessOctree::cellAt names the node that the scene octree itself holds
// the point in (walked from the root, no hash tables), for random points and
// start depths; a rendered view colours each pixel by that node at its
// surface point (reconstructed here in double, independently of the view's
// own reconstruction); and the view changes when a light moves into a region
// that was empty.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "gl/FrameRenderer.hpp"
#include "hashed_support.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/run/RunLayer.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/hashed/OctreeCellView.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "support/DepthPoints.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::hashed {
namespace {

using namespace test_support;
using Cell = LinklessOctree::Cell;

// The node holding `world` as the scene octree has it (SceneOctree::find from
// the root), in cellAt's terms: the linkless octree stores nothing at or
// above the start depth, where every leaf is empty (SceneOctree.hpp).
Cell treeCell(const HashedStructure& hs, const glm::vec3& world) {
  const OctreeBounds& b = hs.bounds();
  glm::uvec3 cell;
  if (!cellOf(b, world, cell)) return {};
  for (unsigned t = 0; t <= b.depth; ++t) {
    const glm::uvec3 c = cell >> (b.depth - t);
    const SceneOctree::NodeView v = hs.tree().find(t, c);
    if (!v.exists || !v.leaf) continue;
    const bool filled = v.lights && !v.lights->empty();
    Cell out;
    if (t <= b.start_depth) {
      EXPECT_FALSE(filled) << "a leaf with lights at depth " << t << " <= start depth " << b.start_depth;
      out.kind = Cell::Kind::Empty;
      out.depth = b.start_depth;
      out.coord = cell >> (b.depth - b.start_depth);
    } else {
      out.kind = filled ? Cell::Kind::Filled : Cell::Kind::Empty;
      out.depth = t;
      out.coord = c;
    }
    return out;
  }
  ADD_FAILURE() << "no leaf holds cell " << cell.x << "," << cell.y << "," << cell.z;
  return {};
}

void expectSameCell(const Cell& got, const Cell& want) {
  ASSERT_EQ(int(got.kind), int(want.kind));
  if (want.kind == Cell::Kind::Outside) return;
  EXPECT_EQ(got.depth, want.depth);
  EXPECT_EQ(got.coord, want.coord);
}

TEST(HashedCellView, CellAtIsTheSceneOctreesLeaf) {
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::size_t filled = 0, empty = 0;
  for (unsigned start_depth : {0u, 1u, 3u, 5u}) {
    for (std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(33), std::size_t(257)}) {
      SCOPED_TRACE("start depth " + std::to_string(start_depth) + ", lights " + std::to_string(n));
      HashedConfig cfg;
      cfg.node_size = "0.5r";
      cfg.start_depth = start_depth;
      HashedStructure hs(cfg);
      hs.build(randomLights(rng, n, 60.0, 0.5, 4.0, false));
      const OctreeBounds& b = hs.bounds();
      for (int i = 0; i < 2000; ++i) {
        // Inside the cube, and a few outside it (past its faces).
        glm::vec3 p = randomPointIn(rng, b);
        if (i % 10 == 0) p = glm::vec3(b.origin + glm::dvec3(uni(rng, -0.2, 1.2) * b.side()));
        const Cell want = treeCell(hs, p);
        expectSameCell(hs.linkless().cellAt(p), want);
        filled += want.kind == Cell::Kind::Filled;
        empty += want.kind == Cell::Kind::Empty;
        if (want.kind == Cell::Kind::Filled) {
          EXPECT_EQ(hs.linkless().cellAt(p).range.count, hs.linkless().lookup(p).count);
        }
      }
    }
  }
  EXPECT_GT(filled, 100u);
  EXPECT_GT(empty, 100u);
}

TEST(HashedCellView, ColoursOfTheKindsNeverMeet) {
  // Filled cells take idColour's levels (every channel >= 64/255), empty ones
  // greys below them, outside a fixed blue: an 8-bit image tells them apart.
  std::mt19937_64 rng(std::random_device{}());
  for (int i = 0; i < 5000; ++i) {
    Cell c;
    c.depth = unsigned(rng() % 16);
    c.coord = glm::uvec3(rng() % 32768, rng() % 32768, rng() % 32768);
    c.kind = Cell::Kind::Filled;
    const Rgb f = octreeCellColour(c);
    EXPECT_GE(std::min({f.r, f.g, f.b}), 64.0f / 255.0f);
    c.kind = Cell::Kind::Empty;
    const Rgb e = octreeCellColour(c);
    EXPECT_EQ(e.r, e.g);
    EXPECT_EQ(e.g, e.b);
    EXPECT_LT(e.r, 64.0f / 255.0f);
    EXPECT_GT(e.r, 0.0f);
  }
  const Rgb o = octreeCellColour(Cell{});
  EXPECT_LT(std::max(o.r, o.g), 64.0f / 255.0f);
  EXPECT_NE(o.r, o.b);
}

// A scene with few lights, so that many surface points lie in empty cells.
const SceneInputs& sparseScene() {
  static const SceneInputs s = [] {
    SceneInputArgs a;
    a.lights = "24";
    return loadSceneInputs(a);
  }();
  return s;
}

constexpr unsigned kW = 200, kH = 120;

Rgb pixel(const std::vector<float>& rgba, std::size_t p) { return {rgba[4 * p], rgba[4 * p + 1], rgba[4 * p + 2]}; }
bool same(const Rgb& a, const Rgb& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

TEST(HashedCellView, EachPixelShowsItsSurfacePointsCell) {
  test::glContext();
  const SceneInputs& in = sparseScene();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  r.setLights(in.lights);
  const Camera& cam = in.cameras.frames.front();
  const gpu::CameraParams params = cam.params(kW, kH);
  for (Pipeline pipeline : {Pipeline::Deferred, Pipeline::Forward}) {
    SCOPED_TRACE(pipeline == Pipeline::Deferred ? "deferred" : "forward");
    HashedAssigner a(pipeline == Pipeline::Deferred ? "hashed-deferred" : "hashed-forward", HashedConfig{});
    r.render(cam, a, {pipeline, false});
    const std::vector<float> view = frameDebugView(r, pipeline, cam, a, "octree-cell");
    ASSERT_EQ(view.size(), std::size_t(kW) * kH * 4);
    const auto depth = r.targets().readDepth(pipeline == Pipeline::Deferred);
    std::size_t covered = 0, wrong = 0, filled = 0, empty = 0;
    for (unsigned y = 0; y < kH; ++y)
      for (unsigned x = 0; x < kW; ++x) {
        const std::size_t p = std::size_t(y) * kW + x;
        const float d = depth[p];
        if (gpu::is_sky_depth(d)) {
          EXPECT_TRUE(same(pixel(view, p), Rgb{0, 0, 0})) << x << "," << y;
          continue;
        }
        ++covered;
        const glm::vec3 world(test::pixelWorldPoint(cam, params, x, y, d));
        const Cell want = treeCell(*a.structure(), world);
        filled += want.kind == Cell::Kind::Filled;
        empty += want.kind == Cell::Kind::Empty;
        wrong += !same(pixel(view, p), octreeCellColour(want));
      }
    EXPECT_GT(filled, covered / 50) << "too few lit cells for the test to mean much";
    EXPECT_GT(empty, covered / 50) << "too few empty cells for the test to mean much";
    // The view reconstructs points in float, this test in double: a point within
    // rounding of a cell face may land in the neighbour. Allow 1%.
    EXPECT_LT(wrong, covered / 100 + 1) << wrong << " of " << covered;
  }
}

TEST(HashedCellView, LightMovedIntoAnEmptyRegionLightsItsCell) {
  test::glContext();
  const unsigned seed = std::random_device{}();
  std::printf("seed %u\n", seed);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 rng(seed);
  const SceneInputs& in = sparseScene();
  FrameRenderer r(test::runtime(), in.scene, kW, kH);
  std::vector<gpu::PointLight> lights = in.lights;
  r.setLights(lights);
  const Camera& cam = in.cameras.frames.front();
  HashedConfig cfg;
  cfg.geometry_mask = true;
  HashedAssigner a("hashed-deferred", cfg);
  a.setScene(&in.scene);
  r.render(cam, a, {Pipeline::Deferred, false});
  const std::vector<float> before = frameDebugView(r, Pipeline::Deferred, cam, a, "octree-cell");
  const auto depth = r.targets().readDepth(true);
  // A random pixel whose point lies in an empty cell, inside the octree's cube.
  std::vector<std::size_t> empty_pixels;
  DebugViewInputs frame;
  frame.width = kW;
  frame.height = kH;
  frame.depth = depth;
  frame.unproject = boundParams(cam.view(), cam.projection(float(kW) / kH), kW, kH);
  for (std::size_t p = 0; p < depth.size(); ++p) {
    glm::vec3 w;
    if (frame.worldAt(unsigned(p % kW), unsigned(p / kW), w) &&
        a.structure()->linkless().cellAt(w).kind == Cell::Kind::Empty)
      empty_pixels.push_back(p);
  }
  ASSERT_FALSE(empty_pixels.empty()) << "no empty cell in view";
  const std::size_t p = empty_pixels[rng() % empty_pixels.size()];
  glm::vec3 point;
  ASSERT_TRUE(frame.worldAt(unsigned(p % kW), unsigned(p / kW), point));
  const std::size_t moved = rng() % lights.size();
  lights[moved].position_radius = {point.x, point.y, point.z, lights[moved].position_radius.w};
  r.setLights(lights);
  r.render(cam, a, {Pipeline::Deferred, false});
  const std::vector<float> after = frameDebugView(r, Pipeline::Deferred, cam, a, "octree-cell");
  const Cell now = a.structure()->linkless().cellAt(point);
  ASSERT_EQ(int(now.kind), int(Cell::Kind::Filled)) << "the moved light's own point has no lights";
  const auto listed = a.structure()->linkless().lightsAt(point);
  EXPECT_NE(std::find(listed.begin(), listed.end(), std::uint32_t(moved)), listed.end());
  EXPECT_FALSE(same(pixel(before, p), pixel(after, p)));
  EXPECT_TRUE(same(pixel(after, p), octreeCellColour(now)));
  EXPECT_GE(std::min({after[4 * p], after[4 * p + 1], after[4 * p + 2]}), 64.0f / 255.0f) << "not a lit cell's colour";
}

}  // namespace
}  // namespace ml::hashed
