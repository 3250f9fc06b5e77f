// Voxel grid settings (host/vct/VoxelGrid.hpp): the validator's one-line
// errors naming --voxels / --levels, the memory figure per configuration,
// and the cube fitted around scene bounds.
#include <gtest/gtest.h>

#include <string>

#include "host/util/Error.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {
namespace {

// The UserError's message, or "" when `s` is accepted.
std::string errorOf(unsigned voxels, unsigned levels) {
  try {
    checkVoxelGrid({voxels, levels, false});
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

TEST(VctGrid, AcceptsPowersOfTwoAndTheirLevels) {
  for (unsigned v = 1; v <= ML_VOXEL_MAX_EDGE; v *= 2)
    for (unsigned l = 1; l <= log2Exact(v) + 1; ++l) EXPECT_EQ(errorOf(v, l), "") << v << " " << l;
}

TEST(VctGrid, RejectsVoxelsNotAPowerOfTwoNamingTheFlag) {
  for (unsigned v : {0u, 3u, 48u, 100u, 1024u, 0xFFFFFFFFu}) {
    const std::string e = errorOf(v, 1);
    EXPECT_EQ(e.rfind("--voxels " + std::to_string(v) + ":", 0), 0u) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

TEST(VctGrid, RejectsLevelsBeyondTheSizeNamingTheFlag) {
  EXPECT_EQ(errorOf(64, 0).rfind("--levels 0:", 0), 0u);
  EXPECT_EQ(errorOf(64, 8).rfind("--levels 8:", 0), 0u);  // 64 -> 32 -> ... -> 1 is 7 levels
  EXPECT_EQ(errorOf(64, 7), "");
  EXPECT_EQ(errorOf(1, 2).rfind("--levels 2:", 0), 0u);
  EXPECT_NE(errorOf(64, 8).find("1..7"), std::string::npos) << errorOf(64, 8);
}

TEST(VctGrid, MemoryPerConfiguration) {
  // 64^3 x 3 levels: 262144 + 32768 + 4096 voxels.
  VoxelGridSettings s{64, 3, false};
  EXPECT_EQ(accumBytes(s), 262144u * 32);
  EXPECT_EQ(radianceBytes(s), (262144u + 32768 + 4096) * 16);
  EXPECT_EQ(anisotropicBytes(s), 0u);
  s.anisotropic = true;
  EXPECT_EQ(anisotropicBytes(s), (32768u + 4096) * 6 * 16);
  EXPECT_EQ(voxelBytes(s), accumBytes(s) + radianceBytes(s) + anisotropicBytes(s));
  EXPECT_EQ(voxelBytes({1, 1, true}), 32u + 16u);
}

TEST(VctGrid, AnisotropicLayoutTilesTheBuffer) {
  // Levels 1.. of edge 8: 64 + 8 + 1 voxels, each direction a block.
  EXPECT_EQ(gpu::voxel_aniso_index(8, 1, 0, 0), 0u);
  EXPECT_EQ(gpu::voxel_aniso_index(8, 1, 5, 63), 6u * 64 - 1);
  EXPECT_EQ(gpu::voxel_aniso_index(8, 2, 0, 0), 6u * 64);
  EXPECT_EQ(gpu::voxel_aniso_index(8, 3, 0, 0), 6u * 72);
  EXPECT_EQ(gpu::voxel_aniso_index(8, 4, 0, 0), 6u * 73);
}

TEST(VctGrid, FitsACubeAroundBounds) {
  Aabb b;
  b.extend({-1, 0, 2});
  b.extend({3, 1, 4});  // longest side 4 (x)
  const gpu::VoxelGridParams p = fitVoxelGrid(b, {64, 4, false});
  EXPECT_EQ(p.edge, 64u);
  EXPECT_EQ(p.levels, 4u);
  const float cell = p.origin_voxel_size.w;
  EXPECT_FLOAT_EQ(cell, 4.0f / 62.0f);
  const glm::vec3 lo(p.origin_voxel_size.x, p.origin_voxel_size.y, p.origin_voxel_size.z);
  const glm::vec3 hi = lo + glm::vec3(64 * cell);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(lo[a] + cell * 0.999f, b.min[a]) << a;  // a voxel of margin
    EXPECT_GE(hi[a] - cell * 0.999f, b.max[a]) << a;
    EXPECT_NEAR(0.5f * (lo[a] + hi[a]), 0.5f * (b.min[a] + b.max[a]), 1e-5f) << a;  // centred
  }
  EXPECT_THROW(fitVoxelGrid(b, {48, 4, false}), UserError);
  const gpu::VoxelGridParams e = fitVoxelGrid(Aabb{}, {1, 1, false});  // no geometry: unit cube
  EXPECT_FLOAT_EQ(e.origin_voxel_size.w, 1.0f);
}

}  // namespace
}  // namespace ml::vct
