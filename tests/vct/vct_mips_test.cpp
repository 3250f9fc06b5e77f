// Voxel mip propagation (kernels/vct/vct_mips.cl through vct::VoxelMips) against
// its C++ twin (host/vct/VoxelMipsReference.hpp), both kernel shapes,
// isotropic and anisotropic: random volumes of edge 1 .. 64, empty, fully
// opaque, checkerboard, one opaque black voxel among empty ones; full and
// partial pyramids (one launch covers up to 3 levels: edge 16 and up need
// more than one). A one-voxel wall must stay opaque at every level, also
// when the parents next to it keep other axes. Bit for bit: the kernels turn
// FP_CONTRACT off and do the twin's additions and multiplications in its
// order (no division or sqrt), so any difference is a bug, not rounding.
// Outputs are poisoned first, and level 0 must come back untouched. Known
// values pin the filters themselves (a twin sharing a kernel's bug would
// otherwise pass).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "host/vct/VoxelMips.hpp"
#include "host/vct/VoxelMipsReference.hpp"
#include "support/shape_support.hpp"
#include "support/TestDevice.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;
constexpr std::uint32_t kPoison = 0xDEADBEEFu;

enum class Pattern { Random, Empty, Opaque, Checkerboard, BlackAmongEmpty };
const char* patternName(Pattern p) {
  const char* names[] = {"random", "empty", "opaque", "checkerboard", "black-among-empty"};
  return names[int(p)];
}

// Level 0 of a volume: premultiplied radiance (radiance up to 4) and opacity.
std::vector<F4> levelZero(unsigned edge, Pattern p, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<F4> v(std::size_t(edge) * edge * edge, F4{0, 0, 0, 0});
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::size_t x = i % edge, y = i / edge % edge, z = i / edge / edge;
    float a = 0;
    switch (p) {
      case Pattern::Random: a = rng() % 3 == 0 ? 0.f : (rng() % 3 == 0 ? 1.f : u(rng)); break;
      case Pattern::Empty: a = 0; break;
      case Pattern::Opaque: a = 1; break;
      case Pattern::Checkerboard: a = float((x + y + z) & 1); break;
      case Pattern::BlackAmongEmpty: v[i] = F4{0, 0, 0, i == v.size() / 2 ? 1.f : 0.f}; continue;
    }
    v[i] = F4{4 * u(rng) * a, 4 * u(rng) * a, 4 * u(rng) * a, a};
  }
  return v;
}

std::vector<std::uint32_t> words(const std::vector<F4>& v) {
  std::vector<std::uint32_t> w(v.size() * 4);
  if (!v.empty()) std::memcpy(w.data(), v.data(), w.size() * 4);
  return w;
}

// First differing float4, as "element i: got (..) want (..)", or "".
std::string firstDifference(const std::vector<F4>& got, const std::vector<F4>& want) {
  const auto g = words(got), w = words(want);
  for (std::size_t i = 0; i < w.size(); ++i)
    if (g[i] != w[i]) {
      const F4 a = got[i / 4], b = want[i / 4];
      return "element " + std::to_string(i / 4) + ": got (" + std::to_string(a.x) + ", " + std::to_string(a.y) + ", " +
             std::to_string(a.z) + ", " + std::to_string(a.w) + ") want (" + std::to_string(b.x) + ", " +
             std::to_string(b.y) + ", " + std::to_string(b.z) + ", " + std::to_string(b.w) + ")";
    }
  return "";
}

gpu::VoxelGridParams grid(unsigned edge, unsigned levels) {
  gpu::VoxelGridParams g{};
  g.origin_voxel_size = {0, 0, 0, 1};
  g.edge = edge;
  g.levels = levels;
  return g;
}

// Runs both filters on `level0` and compares every level with the twins.
void checkVolume(VoxelMips& mips, const std::vector<F4>& level0, unsigned edge, unsigned levels) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const std::size_t all = gpu::voxel_level_offset(edge, levels);
  std::vector<F4> want = level0;
  want.resize(all);
  mipIsotropicTwin(want, edge, levels);
  std::vector<F4> want_aniso;
  mipAnisotropicTwin(want, want_aniso, edge, levels);

  std::vector<F4> poisoned = level0;
  F4 p;
  std::memcpy(&p, std::vector<std::uint32_t>(4, kPoison).data(), 16);
  poisoned.resize(all, p);
  cl::Buffer vol = compute::upload(rt.context(), q, poisoned);
  cl::Buffer aniso(rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(want_aniso.size() * 16, 16));
  compute::poison(q, aniso);
  const gpu::VoxelGridParams g = grid(edge, levels);
  mips.isotropic(q, g, vol);
  mips.anisotropic(q, g, vol, aniso);
  EXPECT_EQ(firstDifference(compute::download<F4>(q, vol, all), want), "") << "isotropic";
  EXPECT_EQ(firstDifference(compute::download<F4>(q, aniso, want_aniso.size()), want_aniso), "") << "anisotropic";
}

class VctMips : public ::testing::TestWithParam<KernelShape> {};

TEST_P(VctMips, MatchTwinOnVolumes) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  VoxelMips mips(compute::ComputeEnv(test::runtime()), compute::Options{.shape = GetParam()});
  const unsigned largest = test::smallTests() ? 16 : 64;
  for (unsigned edge = 1; edge <= largest; edge *= 2)
    for (Pattern p : {Pattern::Random, Pattern::Empty, Pattern::Opaque, Pattern::Checkerboard, Pattern::BlackAmongEmpty})
      for (unsigned levels : {log2Exact(edge) + 1, std::min(2u, log2Exact(edge) + 1), std::min(4u, log2Exact(edge) + 1)}) {
        SCOPED_TRACE("edge=" + std::to_string(edge) + " levels=" + std::to_string(levels) + " " + patternName(p));
        checkVolume(mips, levelZero(edge, p, rng), edge, levels);
      }
}

// Known values at edge 2: child (0,0,0) opaque red, (1,0,0) opaque green.
TEST_P(VctMips, FiltersKnownValues) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  VoxelMips mips(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  std::vector<F4> v(9, F4{0, 0, 0, 0});
  v[0] = {1, 0, 0, 1};
  v[1] = {0, 1, 0, 1};
  cl::Buffer vol = compute::upload(rt.context(), q, v);
  cl::Buffer aniso(rt.context(), CL_MEM_READ_WRITE, 6 * 16);
  compute::poison(q, aniso);
  mips.isotropic(q, grid(2, 2), vol);
  mips.anisotropic(q, grid(2, 2), vol, aniso);
  // Isotropic: along X the pair composites to opacity 1 (colour the mean of
  // both orders), 1/4 of the X columns; along Y and Z two of four columns
  // hold one opaque child: opacity 1/2, the most opaque axis (Y before Z).
  const F4 iso = compute::download<F4>(q, vol, 9)[8];
  EXPECT_EQ(iso.x, 0.25f);
  EXPECT_EQ(iso.y, 0.25f);
  EXPECT_EQ(iso.z, 0.0f);
  EXPECT_EQ(iso.w, 0.5f);
  const auto a = compute::download<F4>(q, aniso, 6);
  // +X meets red first, -X green; along Y and Z each pair keeps its colour.
  EXPECT_EQ(a[ML_VOXEL_DIR_POS_X].x, 0.25f);
  EXPECT_EQ(a[ML_VOXEL_DIR_POS_X].y, 0.0f);
  EXPECT_EQ(a[ML_VOXEL_DIR_POS_X].w, 0.25f);
  EXPECT_EQ(a[ML_VOXEL_DIR_NEG_X].x, 0.0f);
  EXPECT_EQ(a[ML_VOXEL_DIR_NEG_X].y, 0.25f);
  for (unsigned d : {ML_VOXEL_DIR_POS_Y, ML_VOXEL_DIR_NEG_Y, ML_VOXEL_DIR_POS_Z, ML_VOXEL_DIR_NEG_Z}) {
    EXPECT_EQ(a[d].x, 0.25f) << d;
    EXPECT_EQ(a[d].y, 0.25f) << d;
    EXPECT_EQ(a[d].w, 0.5f) << d;
  }
}

// An opaque black voxel is not an empty one: its parent keeps its opacity.
TEST_P(VctMips, OpaqueBlackKeepsOpacity) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  VoxelMips mips(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  std::vector<F4> v(gpu::voxel_level_offset(4, 3), F4{0, 0, 0, 0});
  v[0] = {0, 0, 0, 1};
  cl::Buffer vol = compute::upload(rt.context(), q, v);
  mips.isotropic(q, grid(4, 3), vol);
  const auto got = compute::download<F4>(q, vol, v.size());
  EXPECT_EQ(got[64].w, 0.25f);        // level 1, parent of the black voxel: 1 of 4 columns opaque
  EXPECT_EQ(got[64].x, 0.0f);
  EXPECT_EQ(got[65].w, 0.0f);         // its empty neighbour
  EXPECT_EQ(got[72].w, 1.0f / 16.0f);  // level 2
}

// A one-voxel wall (a plane of opaque voxels across the grid, normal to
// each axis in turn) stays opaque at every level for a cone crossing it: the
// pair along the wall's normal composites to opacity 1 in every column. The
// mean of the 8 children (the former filter) gives 1/2, 1/4, ...
TEST_P(VctMips, OneVoxelWallStaysOpaqueAtEveryLevel) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  VoxelMips mips(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  constexpr unsigned kEdge = 16, kLevels = 5, kWall = 5;
  for (unsigned axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("wall normal to axis " + std::to_string(axis));
    std::vector<F4> v(gpu::voxel_level_offset(kEdge, kLevels), F4{0, 0, 0, 0});
    for (std::size_t i = 0; i < std::size_t(kEdge) * kEdge * kEdge; ++i) {
      const std::size_t c[3] = {i % kEdge, i / kEdge % kEdge, i / kEdge / kEdge};
      if (c[axis] == kWall) v[i] = {0.2f, 0.4f, 0.6f, 1.0f};
    }
    std::vector<F4> want = v;
    mipIsotropicTwin(want, kEdge, kLevels);
    cl::Buffer vol = compute::upload(rt.context(), q, v);
    mips.isotropic(q, grid(kEdge, kLevels), vol);
    const auto got = compute::download<F4>(q, vol, v.size());
    for (unsigned l = 1; l < kLevels; ++l) {
      const unsigned e = kEdge >> l;
      for (std::size_t i = 0; i < std::size_t(e) * e * e; ++i) {
        const std::size_t c[3] = {i % e, i / e % e, i / e / e}, at = gpu::voxel_level_offset(kEdge, l) + i;
        const float a = c[axis] == (kWall >> l) ? 1.0f : 0.0f;
        ASSERT_EQ(got[at].w, a) << "level " << l << " voxel " << i;
        ASSERT_EQ(want[at].w, a) << "twin, level " << l << " voxel " << i;
        ASSERT_EQ(got[at].x, a * 0.2f) << "level " << l << " voxel " << i;  // the wall's colour, not diluted
      }
    }
  }
}

// Neighbouring parents that keep different axes: the CPU shape filters 4
// x-adjacent parents at once and chooses each one's axis by lane, so a row
// holding a wall normal to x, to y, to z and nothing must give each parent
// its own wall, opaque and undiluted (one axis for all 4 would give the y and
// z walls opacity 1/2), and equal the twin.
TEST_P(VctMips, NeighbouringParentsKeepTheirOwnAxis) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  VoxelMips mips(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  constexpr unsigned kEdge = 8, kLevels = 2, kNone = 3;
  // Wall normal per parent x (0 .. 3) in parent rows y = 0 and y = 1 (z = 0).
  const unsigned normals[2][4] = {{0, 1, 2, kNone}, {2, kNone, 1, 0}};
  std::vector<F4> v(gpu::voxel_level_offset(kEdge, kLevels), F4{0, 0, 0, 0});
  for (unsigned py = 0; py < 2; ++py)
    for (unsigned px = 0; px < 4; ++px)
      for (unsigned i = 0; i < 8 && normals[py][px] != kNone; ++i)
        if (((i >> normals[py][px]) & 1) == 0)  // the child layer nearer the origin along the normal
          v[(2 * px + (i & 1)) + kEdge * ((2 * py + ((i >> 1) & 1)) + kEdge * ((i >> 2) & 1))] = {0.2f, 0.4f, 0.6f, 1};
  std::vector<F4> want = v;
  mipIsotropicTwin(want, kEdge, kLevels);
  cl::Buffer vol = compute::upload(rt.context(), q, v);
  mips.isotropic(q, grid(kEdge, kLevels), vol);
  const auto got = compute::download<F4>(q, vol, v.size());
  EXPECT_EQ(firstDifference(got, want), "");
  for (unsigned py = 0; py < 2; ++py)
    for (unsigned px = 0; px < 4; ++px) {
      const F4 p = got[kEdge * kEdge * kEdge + px + 4 * py];
      const float a = normals[py][px] == kNone ? 0.0f : 1.0f;
      EXPECT_EQ(p.w, a) << "parent x " << px << " y " << py;
      EXPECT_EQ(p.x, a * 0.2f) << "parent x " << px << " y " << py;
    }
}

TEST_P(VctMips, RejectsSmallBuffers) {
  auto& rt = test::runtime();
  VoxelMips mips(compute::ComputeEnv(rt), compute::Options{.shape = GetParam()});
  cl::Buffer small(rt.context(), CL_MEM_READ_WRITE, 16 * 64);
  EXPECT_THROW(mips.isotropic(rt.queue(), grid(4, 2), small), std::invalid_argument);
  cl::Buffer tiny(rt.context(), CL_MEM_READ_WRITE, 16 * 8);  // level 1's 6 x 8 voxels need 48 float4
  EXPECT_THROW(mips.anisotropic(rt.queue(), grid(4, 3), small, tiny), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Shapes, VctMips, ::testing::ValuesIn(test::kBothShapes),
                         [](const auto& info) { return test::shapeLabel(info.param); });

}  // namespace
}  // namespace ml::vct
