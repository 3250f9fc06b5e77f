// GL voxelization (gl/VoxelizePass) of shapes built in code, against exact
// triangle/voxel overlap: every voxel whose interior a surface crosses is
// filled, no voxel farther than one voxel from the surface is, and filled
// voxels average to the surface's albedo (within 1/255: all fragments carry
// the same colour, the sum is of values rounded to 1/255) and normal (within
// 1e-3 in the dot product: sums of normals rounded to 1/1024), for voxels
// whose one-voxel neighbourhood sees one face normal only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "gl/GlCheck.hpp"
#include "gl/SceneGpu.hpp"
#include "host/vct/VoxelizePass.hpp"
#include "host/util/Error.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"
#include "support/TriangleBox.hpp"

namespace ml {
namespace {

using test::Triangle;

// A shape in grid units (voxel (i, j, k) spans [i, i+1] x ...), with a world
// grid to place it in.
struct Shape {
  std::string name;
  std::vector<Triangle> tris;
  bool check_normals = true;  // false where opposite faces share voxels (thin wall)
};

glm::dvec3 faceNormal(const Triangle& t) { return glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0])); }

// Two triangles, counter-clockwise seen from cross(u, v).
void addQuad(std::vector<Triangle>& out, glm::dvec3 c, glm::dvec3 u, glm::dvec3 v) {
  out.push_back({{c - u - v, c + u - v, c + u + v}});
  out.push_back({{c - u - v, c + u + v, c - u + v}});
}

// A box of half extents `half` along the columns of the rotation `r`, faces outward.
std::vector<Triangle> boxTriangles(glm::dvec3 c, glm::dvec3 half, const glm::dmat3& r) {
  std::vector<Triangle> out;
  for (int a = 0; a < 3; ++a) {
    const glm::dvec3 n = r[a] * half[a], u = r[(a + 1) % 3] * half[(a + 1) % 3], v = r[(a + 2) % 3] * half[(a + 2) % 3];
    addQuad(out, c + n, u, v);
    addQuad(out, c - n, v, u);
  }
  return out;
}

glm::dmat3 randomRotation(std::mt19937& rng, double max_angle) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  glm::dvec3 axis;
  do axis = {u(rng), u(rng), u(rng)};
  while (glm::dot(axis, axis) < 0.01);
  axis = glm::normalize(axis);
  const double a = u(rng) * max_angle, c = std::cos(a), s = std::sin(a);
  const glm::dmat3 k(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x, 0);  // cross-product matrix
  return glm::dmat3(1.0) + s * k + (1 - c) * k * k;
}

Scene sceneFromGrid(const Shape& shape, const gpu::VoxelGridParams& grid, glm::vec4 color) {
  Scene s;
  s.source = shape.name;
  const glm::dvec3 origin(grid.origin_voxel_size.x, grid.origin_voxel_size.y, grid.origin_voxel_size.z);
  const double vs = grid.origin_voxel_size.w;
  for (const Triangle& t : shape.tris) {
    const glm::vec3 n(faceNormal(t));
    for (const auto& p : t.p) {
      const glm::vec3 w(origin + p * vs);
      s.vertices.push_back({w, n, glm::vec2(0.0f)});
      s.indices.push_back(static_cast<std::uint32_t>(s.indices.size()));
      s.bounds.extend(w);
    }
  }
  s.materials.push_back({color, -1});
  s.batches.push_back({0, static_cast<std::uint32_t>(s.indices.size()), 0});
  return s;
}

std::vector<gpu::VoxelAccum> voxelize(const Shape& shape, const gpu::VoxelGridParams& grid, glm::vec4 color,
                                      VoxelizeOptions options = {}) {
  test::glContext();
  const Scene scene = sceneFromGrid(shape, grid, color);
  SceneGpu gpu_scene(scene);
  VoxelizePass pass(options);
  SharedBuffer accum(test::runtime(), sizeof(gpu::VoxelAccum), "test accum");
  pass.run(gpu_scene, grid, accum, nullptr);
  std::vector<gpu::VoxelAccum> out(std::size_t(grid.edge) * grid.edge * grid.edge);
  accum.download(out.data(), out.size() * sizeof(gpu::VoxelAccum));
  return out;
}

struct VoxelCheck {
  std::size_t missed = 0, outside = 0, not_crossed = 0, filled = 0, bad_albedo = 0, bad_normal = 0, normals_checked = 0;
};

// Triangles overlapping the voxel's box of half size `half`.
std::vector<const Triangle*> overlapping(const Shape& s, glm::dvec3 centre, double half) {
  std::vector<const Triangle*> out;
  for (const Triangle& t : s.tris)
    if (test::triangleOverlapsBox(t, centre, glm::dvec3(half))) out.push_back(&t);
  return out;
}

void checkFilledVoxel(const gpu::VoxelAccum& v, const Shape& s, glm::dvec3 centre, glm::vec4 color, VoxelCheck& r) {
  const double count = v.albedo_count[3];
  for (int c = 0; c < 3; ++c)
    if (std::abs(v.albedo_count[c] / count / 255.0 - color[c]) > 1.0 / 255.0) ++r.bad_albedo;
  if (!s.check_normals) return;
  const auto near = overlapping(s, centre, 1.5);
  const glm::dvec3 n = faceNormal(*near.at(0));
  for (const Triangle* t : near)
    if (glm::dot(faceNormal(*t), n) < 1.0 - 1e-9) return;  // an edge or corner: normals mix
  ++r.normals_checked;
  const glm::dvec3 sum(v.normal_sum[0], v.normal_sum[1], v.normal_sum[2]);
  if (glm::dot(sum, sum) == 0.0 || glm::dot(glm::normalize(sum), n) < 1.0 - 1e-3) ++r.bad_normal;
}

VoxelCheck checkVoxels(const std::vector<gpu::VoxelAccum>& got, const Shape& s, unsigned edge, glm::vec4 color) {
  VoxelCheck r;
  for (unsigned z = 0; z < edge; ++z)
    for (unsigned y = 0; y < edge; ++y)
      for (unsigned x = 0; x < edge; ++x) {
        const gpu::VoxelAccum& v = got[x + edge * (y + std::size_t(edge) * z)];
        const glm::dvec3 centre = glm::dvec3(x, y, z) + 0.5;
        const bool filled = v.albedo_count[3] > 0;
        // Interior crossed: the box shrunk by 1e-3 voxel (a face on a voxel boundary may fill either side).
        if (!filled && !overlapping(s, centre, 0.5 - 1e-3).empty()) ++r.missed;
        if (!filled) continue;
        ++r.filled;
        if (overlapping(s, centre, 1.5).empty()) {
          ++r.outside;
          continue;
        }
        // Stricter than the margin: the clip makes the fill exact up to rounding.
        if (overlapping(s, centre, 0.5 + 1e-2).empty()) ++r.not_crossed;
        checkFilledVoxel(v, s, centre, color, r);
      }
  return r;
}

gpu::VoxelGridParams randomGrid(std::mt19937& rng, unsigned edge) {
  std::uniform_real_distribution<float> pos(-50.0f, 50.0f), size(0.05f, 2.0f);
  gpu::VoxelGridParams g{};
  g.origin_voxel_size = {pos(rng), pos(rng), pos(rng), size(rng)};
  g.edge = edge;
  g.levels = 1;
  return g;
}

// Shapes in grid units, inside the grid with room to spare.
Shape axisAlignedBox(std::mt19937& rng, double e) {
  std::uniform_real_distribution<double> c(0.4 * e, 0.6 * e), h(0.15 * e, 0.3 * e);
  return {"axis-aligned box", boxTriangles({c(rng), c(rng), c(rng)}, {h(rng), h(rng), h(rng)}, glm::dmat3(1.0))};
}

Shape tiltedPlane(std::mt19937& rng, double e) {
  std::uniform_real_distribution<double> c(0.45 * e, 0.55 * e);
  const glm::dmat3 r = randomRotation(rng, 3.14159265358979);
  Shape s{"tilted plane", {}};
  addQuad(s.tris, {c(rng), c(rng), c(rng)}, r[0] * 0.3 * e, r[1] * 0.3 * e);
  return s;
}

// A slab thinner than a voxel (0.1 to 0.8 voxels), slightly rotated, at a random sub-voxel offset.
Shape thinWall(std::mt19937& rng, double e) {
  std::uniform_real_distribution<double> c(0.45 * e, 0.55 * e), t(0.05, 0.4);
  const glm::dmat3 r = randomRotation(rng, 0.3);
  return {"thin wall", boxTriangles({c(rng), c(rng), c(rng)}, {0.3 * e, 0.3 * e, t(rng)}, r), false};
}

glm::vec4 randomColor(std::mt19937& rng) {
  std::uniform_int_distribution<int> c(0, 255);
  return {c(rng) / 255.0f, c(rng) / 255.0f, c(rng) / 255.0f, 1.0f};
}

class VctVoxelize : public ::testing::TestWithParam<unsigned> {};

TEST_P(VctVoxelize, KnownShapesFillCrossedVoxelsOnly) {
  const unsigned edge = GetParam();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (auto make : {axisAlignedBox, tiltedPlane, thinWall}) {
    const Shape shape = make(rng, edge);
    SCOPED_TRACE(shape.name);
    const gpu::VoxelGridParams grid = randomGrid(rng, edge);
    const glm::vec4 color = randomColor(rng);
    const VoxelCheck r = checkVoxels(voxelize(shape, grid, color), shape, edge, color);
    EXPECT_GT(r.filled, 0u);
    EXPECT_EQ(r.missed, 0u) << "crossed voxels left empty";
    EXPECT_EQ(r.outside, 0u) << "filled voxels farther than one voxel from the surface";
    EXPECT_EQ(r.not_crossed, 0u) << "filled voxels the surface does not cross (beyond 0.01 voxel)";
    EXPECT_EQ(r.bad_albedo, 0u);
    EXPECT_EQ(r.bad_normal, 0u) << "of " << r.normals_checked;
    if (shape.check_normals && edge >= 32) {
      EXPECT_GT(r.normals_checked, 0u);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Edges, VctVoxelize, ::testing::Values(8u, 32u, 64u),
                         [](const auto& info) { return "edge" + std::to_string(info.param); });

// The check above can fail: without dilation, pixels a triangle covers only
// partly, away from their centre, get no fragment, and crossed voxels stay
// empty. The claim is on both shapes together: an axis-aligned box, and now
// and then a thin wall rotated by almost nothing, fills its crossed voxels by
// pixel centres alone; a tilted plane cannot.
TEST(VctVoxelizeCheck, WithoutDilationCrossedVoxelsAreMissed) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::size_t missed_without = 0, filled_with = 0, filled_without = 0;
  for (auto make : {tiltedPlane, thinWall}) {
    const Shape shape = make(rng, 32);
    SCOPED_TRACE(shape.name);
    const gpu::VoxelGridParams grid = randomGrid(rng, 32);
    const glm::vec4 color = randomColor(rng);
    const VoxelCheck with = checkVoxels(voxelize(shape, grid, color), shape, 32, color);
    const VoxelCheck without = checkVoxels(voxelize(shape, grid, color, {.dilate = false}), shape, 32, color);
    EXPECT_EQ(with.missed, 0u);
    missed_without += without.missed;
    filled_with += with.filled;
    filled_without += without.filled;
    std::printf("%s: %zu filled, %zu missed without dilation\n", shape.name.c_str(), with.filled, without.missed);
  }
  EXPECT_GT(missed_without, 0u);
  EXPECT_LT(filled_without, filled_with);
}

// Cleared before each run (a second run gives the same sums, not twice them),
// timed as `vct-voxelize`, readable by OpenCL, and the grid fitted around the
// scene holds all of it.
TEST(VctVoxelizePass, ClearsTimesAndFitsTheScene) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  const Shape shape = axisAlignedBox(rng, 16);
  const glm::vec4 color = randomColor(rng);
  const Scene scene = sceneFromGrid(shape, randomGrid(rng, 16), color);
  const gpu::VoxelGridParams grid = vct::fitVoxelGrid(scene.bounds, {16, 5, false});
  SceneGpu gpu_scene(scene);
  VoxelizePass pass;
  SharedBuffer accum(test::runtime(), 1, "test accum");
  GlPassTimer timer;
  std::vector<gpu::VoxelAccum> first(16 * 16 * 16), second(first.size());
  pass.run(gpu_scene, grid, accum, &timer);
  accum.download(first.data(), first.size() * sizeof(gpu::VoxelAccum));
  pass.run(gpu_scene, grid, accum, &timer);
  accum.download(second.data(), second.size() * sizeof(gpu::VoxelAccum));
  PassTimings t;
  timer.collect(t);
  EXPECT_GT(t.get("vct-voxelize"), 0.0);
  std::size_t filled = 0, differ = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    filled += first[i].albedo_count[3] > 0;
    differ += std::memcmp(&first[i], &second[i], sizeof(gpu::VoxelAccum)) != 0;
  }
  EXPECT_GT(filled, 0u);
  EXPECT_EQ(differ, 0u);
  const std::size_t bytes = first.size() * sizeof(gpu::VoxelAccum);
  EXPECT_EQ(accum.used(), bytes);
  // OpenCL reads the same sums from the shared buffer.
  std::vector<gpu::VoxelAccum> from_cl(first.size());
  std::memset(from_cl.data(), 0xAB, from_cl.size() * sizeof(gpu::VoxelAccum));
  cl::CommandQueue& q = test::runtime().queue();
  accum.acquireForCl(q, ClAccess::Read);
  q.enqueueReadBuffer(accum.cl(), CL_TRUE, 0, bytes, from_cl.data());
  accum.releaseToGl(q);
  EXPECT_EQ(std::memcmp(from_cl.data(), first.data(), bytes), 0);
  // The fitted cube holds the scene's bounds strictly inside.
  const glm::vec3 origin(grid.origin_voxel_size.x, grid.origin_voxel_size.y, grid.origin_voxel_size.z);
  for (int a = 0; a < 3; ++a) {
    const float lo = origin[a], hi = lo + 16 * grid.origin_voxel_size.w;
    EXPECT_LT(lo, scene.bounds.min[a]);
    EXPECT_GT(hi, scene.bounds.max[a]);
  }
}

// Grids built by hand are checked before anything is drawn (fitted ones are
// checked by vct::fitVoxelGrid, tests/vct/vct_grid_test.cpp).
TEST(VctVoxelizePass, BadGridsAreUserErrors) {
  Aabb b;
  b.extend({0, 0, 0});
  b.extend({1, 2, 3});
  const gpu::VoxelGridParams good = vct::fitVoxelGrid(b, {64, 7, false});
  EXPECT_NO_THROW(checkVoxelGrid(good));
  const auto with = [&](unsigned edge, unsigned levels, float size) {
    gpu::VoxelGridParams g = good;
    g.edge = edge;
    g.levels = levels;
    g.origin_voxel_size.w = size;
    return g;
  };
  EXPECT_THROW(checkVoxelGrid(with(48, 1, 0.1f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(0, 1, 0.1f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(1024, 1, 0.1f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(64, 0, 0.1f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(64, 8, 0.1f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(64, 7, 0.0f)), UserError);
  EXPECT_THROW(checkVoxelGrid(with(64, 7, -1.0f)), UserError);
}

// The Cornell box as loaded from glTF, in a fitted grid: the voxels the red and
// green walls' inner faces cross (away from the other walls) are filled with
// those walls' albedo only, so per-batch materials reach the sums.
TEST(VctVoxelizePass, CornellWallsCarryTheirAlbedo) {
  test::glContext();
  const Scene scene = loadGltfScene(std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/cornell.gltf");
  constexpr unsigned kEdge = 32;
  const gpu::VoxelGridParams grid = vct::fitVoxelGrid(scene.bounds, {kEdge, 1, false});
  SceneGpu gpu_scene(scene);
  VoxelizePass pass;
  SharedBuffer accum(test::runtime(), 1, "test accum");
  pass.run(gpu_scene, grid, accum, nullptr);
  std::vector<gpu::VoxelAccum> v(kEdge * kEdge * kEdge);
  accum.download(v.data(), v.size() * sizeof(gpu::VoxelAccum));
  const glm::vec3 origin(grid.origin_voxel_size.x, grid.origin_voxel_size.y, grid.origin_voxel_size.z);
  const float vs = grid.origin_voxel_size.w;
  const auto cell = [&](float w, int axis) { return unsigned((w - origin[axis]) / vs); };
  struct Wall {
    float x;
    glm::vec3 albedo;  // scripts/make_cornell_box.py
  };
  std::size_t checked = 0;
  for (const Wall& wall : {Wall{-1.0f + 1e-3f, {0.63f, 0.065f, 0.05f}}, Wall{1.0f - 1e-3f, {0.14f, 0.45f, 0.091f}}}) {
    const unsigned x = cell(wall.x, 0);
    for (unsigned z = cell(-0.8f, 2); z <= cell(0.8f, 2); ++z)
      for (unsigned y = cell(0.3f, 1); y <= cell(1.8f, 1); ++y) {
        const gpu::VoxelAccum& a = v[x + kEdge * (y + kEdge * z)];
        ASSERT_GT(a.albedo_count[3], 0u) << "voxel " << x << " " << y << " " << z;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(a.albedo_count[c] / double(a.albedo_count[3]) / 255.0, wall.albedo[c], 1.0 / 255.0);
        ++checked;
      }
  }
  EXPECT_GT(checked, 200u);
}

// A grid whose sums exceed the GL's storage block limit is reported, not
// voxelized into a truncated buffer.
TEST(VctVoxelizePass, GridBeyondTheStorageBlockLimitIsAUserError) {
  test::glContext();
  GLint64 max_block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  const std::uint64_t largest = std::uint64_t(ML_VOXEL_MAX_EDGE) * ML_VOXEL_MAX_EDGE * ML_VOXEL_MAX_EDGE * sizeof(gpu::VoxelAccum);
  if (std::uint64_t(max_block) >= largest) GTEST_SKIP() << "this GL takes the largest grid";
  unsigned edge = ML_VOXEL_MAX_EDGE;
  while (edge > 1 && std::uint64_t(edge / 2) * (edge / 2) * (edge / 2) * sizeof(gpu::VoxelAccum) > std::uint64_t(max_block)) edge /= 2;
  std::mt19937 rng(1);
  const Scene scene = sceneFromGrid(axisAlignedBox(rng, 8), randomGrid(rng, 8), {1, 1, 1, 1});
  SceneGpu gpu_scene(scene);
  VoxelizePass pass;
  SharedBuffer accum(test::runtime(), 1, "test accum");
  EXPECT_THROW(pass.run(gpu_scene, vct::fitVoxelGrid(scene.bounds, {edge, 1, false}), accum, nullptr), UserError);
  glCheck("after the refused grid");
}

}  // namespace
}  // namespace ml
