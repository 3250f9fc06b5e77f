// gl/VoxelTextures through vct::VctPipeline: every level of the mip-mapped
// RGBA16F 3D textures holds the radiance volume's level (and, anisotropic,
// each direction texture its direction's level, level 0 the isotropic one),
// read back as floats and compared with the buffer's floats rounded to half:
// within half an ulp of half precision plus GL's rounding freedom (one ulp,
// 2^-10 relative; 2^-24 absolute for half's subnormals). The textures are
// filled with NaN-free garbage first (a previous volume of other lights), so a
// level left unwritten fails.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "gl/GlCheck.hpp"
#include "gl/SceneGpu.hpp"
#include "host/scene/LightSet.hpp"
#include "host/vct/VctPipeline.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;

std::vector<F4> readLevel(GLuint texture, unsigned level, unsigned edge) {
  std::vector<F4> out(std::size_t(edge) * edge * edge, F4{-7, -7, -7, -7});
  glGetTextureImage(texture, static_cast<GLint>(level), GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(out.size() * sizeof(F4)), out.data());
  glCheck("reading a voxel texture level back");
  return out;
}

// "" when every texel matches its voxel, else the first mismatch.
std::string compare(const std::vector<F4>& texels, const F4* voxels, const std::string& what) {
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const float g[4] = {texels[i].x, texels[i].y, texels[i].z, texels[i].w};
    const float w[4] = {voxels[i].x, voxels[i].y, voxels[i].z, voxels[i].w};
    for (int c = 0; c < 4; ++c)
      if (!(std::fabs(g[c] - w[c]) <= std::ldexp(std::fabs(w[c]), -10) + std::ldexp(1.0f, -24)))
        return what + " texel " + std::to_string(i) + " component " + std::to_string(c) + ": got " +
               std::to_string(g[c]) + " want " + std::to_string(w[c]);
  }
  return "";
}

TEST(VctTextures, EveryLevelEqualsTheVolume) {
  test::glContext();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  const Scene scene = loadGltfScene(dir + "cornell.gltf");
  auto lights = loadLightsJson(dir + "lights.json");
  const unsigned edges[] = {4, 8, 16, 32};
  const unsigned edge = edges[rng() % 4];
  const unsigned levels = 1 + unsigned(rng() % (log2Exact(edge) + 1));
  const bool aniso = levels > 1 && rng() % 4 != 0;
  SCOPED_TRACE("edge " + std::to_string(edge) + " levels " + std::to_string(levels) + " anisotropic " +
               std::to_string(aniso));
  SceneGpu gpu_scene(scene);
  VctPipelineOptions o;
  o.grid = {edge, levels, aniso};
  VctPipeline p(test::runtime(), o, scene.bounds);
  PassTimings t;
  // A first volume with the lights elsewhere leaves other values in every texel.
  std::vector<gpu::PointLight> elsewhere = lights;
  for (auto& l : elsewhere) l.color = {l.color.x * 0.5f, l.color.y * 0.25f, l.color.z * 0.75f, l.color.w};
  p.update(gpu_scene, elsewhere, t);
  p.update(gpu_scene, lights, t);
  EXPECT_GT(t.get("vct-textures"), 0.0);
  VoxelVolume& v = p.volume();
  std::vector<F4> radiance(radianceBytes(v.settings()) / sizeof(F4));
  v.radiance().download(radiance.data(), radiance.size() * sizeof(F4));
  std::vector<F4> dirs(anisotropicBytes(v.settings()) / sizeof(F4));
  if (aniso) v.anisotropic()->download(dirs.data(), dirs.size() * sizeof(F4));
  bool lit = false;
  for (unsigned l = 0; l < levels; ++l) {
    const unsigned e = edge >> l;
    const F4* level = radiance.data() + gpu::voxel_level_offset(edge, l);
    const auto texels = readLevel(p.textures().radiance(), l, e);
    EXPECT_EQ(compare(texels, level, "radiance level " + std::to_string(l)), "");
    for (const F4& x : texels) lit |= x.x > 0;
    if (!aniso) continue;
    for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d) {
      const F4* want = l == 0 ? level : dirs.data() + gpu::voxel_aniso_index(edge, l, d, 0);
      EXPECT_EQ(compare(readLevel(p.textures().direction(d), l, e), want,
                        "direction " + std::to_string(d) + " level " + std::to_string(l)),
                "");
    }
  }
  EXPECT_TRUE(lit) << "no texel lit: the comparison would prove nothing";
}

}  // namespace
}  // namespace ml::vct
