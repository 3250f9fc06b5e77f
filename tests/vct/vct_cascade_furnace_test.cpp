// The furnace of the cone tracing (vct_furnace_test.cpp) through a
// camera-centred cascade (--vct-cascades L, host/vct/VoxelCascade.hpp): a
// closed box, every voxel of every level outside its interior opaque with the
// same radiance L, so traceDiffuse's irradiance / pi must equal L and its
// ambient occlusion 0 wherever the cones start and whichever levels they
// read. The levels are laid out as the pipeline lays them (innerCascadeLevel,
// placeCascade's rule: inner level c has half the voxel of level c + 1, kInnerLevels mips,
// toroidal, its corner on a kInnerStep lattice around a random eye, so the
// stored volume is scrolled), each filled directly (the box's faces lie on
// every level's voxel faces) and mip-mapped by the mip filters' C++ twins.
// For each L = 1..kMaxCascades, isotropic and anisotropic, several cone sets:
// points whose cones start in each level (inside its window by the shader's
// margin, outside the next finer one's), so every level is a cone's first
// and every coarser one its next. Stated tolerance: 2% of L, as for the single
// grid (cones stop at opacity 0.99; RGBA16F texels). The test can fail: with
// the weights broken it must.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "host/vct/ConeTracing.hpp"
#include "host/vct/VoxelCascade.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "host/vct/VoxelMipsReference.hpp"
#include "host/vct/VoxelTextures.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"
#include "vct/cone_furnace.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;
constexpr unsigned kEdge = 64, kOuterLevels = 4;
constexpr float kOuterVoxel = 2.0f / kEdge;  // the outermost level spans [-1, 1]^3
constexpr float kBox = 0.375f;               // interior [-kBox, kBox]^3: 12 outer voxels, on every level's faces
constexpr float kTolerance = 0.02f;
const F4 kL{0.3f, 0.5f, 0.7f, 1.0f};

// Level c of `cascades`, the inner ones around `eye` as placeCascade puts them.
gpu::VoxelGridParams levelParams(unsigned cascades, unsigned c, const glm::vec3& eye) {
  const gpu::VoxelGridParams outer{{-1.0f, -1.0f, -1.0f, kOuterVoxel}, kEdge, kOuterLevels, 0, 0};
  if (c + 1 == cascades) return outer;
  VoxelGridSettings s;
  s.voxels = kEdge;
  s.levels = kOuterLevels;
  const gpu::VoxelGridParams p = innerCascadeLevel(outer, s, cascades, c, eye);
  EXPECT_EQ(p.levels, kInnerLevels);  // the window's corner is what the test varies, not its mips
  return p;
}

// One level's textures: level 0 holds L outside the box (stored where the
// level's addressing puts each window voxel), the rest the twins' mips.
void fillLevel(const gpu::VoxelGridParams& p, bool aniso, VoxelTextures& textures) {
  std::vector<F4> radiance(voxelsAllLevels(p.edge, p.levels), F4{0, 0, 0, 0});
  const gpu::VoxelCorner k = gpu::voxel_corner(p);
  const float o[3] = {p.origin_voxel_size.x, p.origin_voxel_size.y, p.origin_voxel_size.z}, vs = p.origin_voxel_size.w;
  for (unsigned i = 0; i < p.edge * p.edge * p.edge; ++i) {
    const gpu::VoxelWindow w = gpu::voxel_window(p, i);
    const unsigned v[3] = {w.x, w.y, w.z};
    const int kk[3] = {k.x, k.y, k.z};
    bool wall = false;
    for (int a = 0; a < 3; ++a) {
      const float centre = p.wrap ? (float(kk[a]) + float(v[a]) + 0.5f) * vs : o[a] + (float(v[a]) + 0.5f) * vs;
      wall |= std::fabs(centre) > kBox;
    }
    if (wall) radiance[i] = kL;
  }
  mipIsotropicTwin(radiance, p.edge, p.levels);
  std::vector<F4> dirs;
  if (aniso) mipAnisotropicTwin(radiance, dirs, p.edge, p.levels);
  const GLuint r = furnace::upload(radiance), d = aniso ? furnace::upload(dirs) : 0;
  textures.unpack(p, r, d, nullptr);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glDeleteBuffers(1, &r);
  if (d) glDeleteBuffers(1, &d);
}

// How far x lies inside p's window, in p's voxels (< 0: outside).
float insideVoxels(const gpu::VoxelGridParams& p, const F4& x) {
  const float o[3] = {p.origin_voxel_size.x, p.origin_voxel_size.y, p.origin_voxel_size.z}, v[3] = {x.x, x.y, x.z};
  float m = 1e30f;
  for (int a = 0; a < 3; ++a) {
    const float g = (v[a] - o[a]) / p.origin_voxel_size.w;
    m = std::min({m, g, float(p.edge) - g});
  }
  return m;
}

struct Cascade {
  std::vector<gpu::VoxelGridParams> params;
  std::vector<std::unique_ptr<VoxelTextures>> textures;
  ShaderProgram program;

  Cascade(unsigned cascades, const glm::vec3& eye, bool aniso)
      : program({"test/test_vct_cones.comp"}, coneTracingDefines(cascades)) {
    for (unsigned c = 0; c < cascades; ++c) {
      params.push_back(levelParams(cascades, c, eye));
      textures.push_back(std::make_unique<VoxelTextures>());
      fillLevel(params.back(), aniso, *textures.back());
    }
  }
  ConeTraceSetup setup(bool aniso, unsigned cones, float aperture) const {
    ConeTraceSetup s{params.back(), textures.back().get(), aniso, diffuseCones(cones), aperture, ConeBreak::None, {}};
    for (std::size_t c = 0; c < params.size(); ++c) s.levels.push_back({params[c], textures[c].get()});
    return s;
  }
};

// Per level, up to `count` points whose cones start there (inside its window
// by 4 of its voxels, kLevelMargin's 3 and one to spare; outside the finer
// level's by as much), at least 3 outer voxels inside the box.
std::vector<std::vector<F4>> pointsPerLevel(std::mt19937_64& rng, const std::vector<gpu::VoxelGridParams>& params,
                                            int count) {
  std::vector<std::vector<F4>> points(params.size());
  const float lo = -kBox + 3 * kOuterVoxel, hi = kBox - 3 * kOuterVoxel;
  for (int tries = 0; tries < 200000; ++tries) {
    std::vector<F4> p, unused;
    furnace::randomPoints(rng, lo, hi, p, unused, 1);
    for (std::size_t c = 0; c < params.size(); ++c) {
      const bool in = c + 1 == params.size() || insideVoxels(params[c], p[0]) >= 4.0f;
      const bool finer_out = c == 0 || insideVoxels(params[c - 1], p[0]) < -4.0f;
      if (in && finer_out && points[c].size() < std::size_t(count)) points[c].push_back(p[0]);
      if (in) break;  // it starts in the finest level that holds it
    }
  }
  return points;
}

TEST(VctCascadeFurnace, UniformRadianceGivesPiLFromEveryLevel) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-0.15f, 0.15f);
  for (unsigned cascades = 1; cascades <= kMaxCascades; ++cascades) {
    const glm::vec3 eye(u(rng), u(rng), u(rng));
    for (bool aniso : {false, true}) {
      Cascade k(cascades, eye, aniso);
      const auto per_level = pointsPerLevel(rng, k.params, 100);
      for (unsigned c = 0; c < cascades; ++c) {
        if (per_level[c].empty()) continue;  // no point of the box starts here (the finer window holds it all)
        std::vector<F4> normals, unused;
        furnace::randomPoints(rng, 0, 0, unused, normals, int(per_level[c].size()));
        for (auto [cones, aperture] : {std::pair{5u, 60.0f}, std::pair{9u, 45.0f}, std::pair{16u, 30.0f}}) {
          SCOPED_TRACE("cascades " + std::to_string(cascades) + " anisotropic " + std::to_string(aniso) +
                       " start level " + std::to_string(c) + " cones " + std::to_string(cones));
          ConeTraceSetup s = k.setup(aniso, cones, aperture);
          const auto [err, ao] = furnace::worst(furnace::trace(k.program, s, per_level[c], normals), kL);
          std::printf("cascades %u anisotropic %d start level %u (%3zu points) cones %2u aperture %2.0f: worst "
                      "|E/pi - L| / L %.4f, AO %.4f\n",
                      cascades, int(aniso), c, per_level[c].size(), cones, double(aperture), double(err), double(ao));
          EXPECT_LE(err, kTolerance);
          EXPECT_LE(ao, kTolerance);
          s.broken = ConeBreak::Weights;
          EXPECT_GT(furnace::worst(furnace::trace(k.program, s, per_level[c], normals), kL).first, kTolerance)
              << "broken weights pass";
        }
      }
    }
  }
}

// Every level is some cone's first: the per-level points exist where the
// windows leave room (the test above would pass vacuously otherwise).
TEST(VctCascadeFurnace, EveryLevelStartsSomeCones) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (unsigned cascades = 2; cascades <= kMaxCascades; ++cascades) {
    std::vector<gpu::VoxelGridParams> params;
    for (unsigned c = 0; c < cascades; ++c) params.push_back(levelParams(cascades, c, glm::vec3(0.05f, -0.1f, 0.0f)));
    const auto per_level = pointsPerLevel(rng, params, 20);
    // Every level up to the one 1.0 wide starts cones (the box, 0.56 wide
    // inside its margin, reaches out of the windows inside it); the
    // outermost starts none when a level 1.0 wide holds the whole box.
    for (unsigned c = 0; c < cascades; ++c) {
      const float width = kEdge * params[c].origin_voxel_size.w;
      if (c == 0 || width < 1.5f) {
        EXPECT_EQ(per_level[c].size(), 20u) << "cascades " << cascades << " level " << c << " width " << width;
      }
    }
  }
}

}  // namespace
}  // namespace ml::vct
