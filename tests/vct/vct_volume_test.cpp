// vct::VoxelVolume: buffers sized by the settings, shared with GL. End to
// end on a small grid: GL uploads an accumulation buffer, the kernels inject
// (brute force) and build both mip volumes on the shared buffers, GL reads
// them back, and they equal the C++ twins.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host/scene/LightSet.hpp"
#include "host/util/Error.hpp"
#include "host/vct/InjectTwin.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "host/vct/VoxelMips.hpp"
#include "host/vct/VoxelMipsReference.hpp"
#include "host/vct/VoxelVolume.hpp"
#include "support/FpTolerance.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml::vct {
namespace {

using F4 = gpu::ml_float4;

TEST(VctVolume, SizesFollowTheSettings) {
  test::glContext();
  const VoxelGridSettings s{16, 3, true};
  Aabb b;
  b.extend({0, 0, 0});
  b.extend({1, 1, 1});
  VoxelVolume v(test::runtime(), s, fitVoxelGrid(b, s));
  EXPECT_GE(v.accum().size(), accumBytes(s));
  EXPECT_GE(v.radiance().size(), radianceBytes(s));
  ASSERT_NE(v.anisotropic(), nullptr);
  EXPECT_GE(v.anisotropic()->size(), anisotropicBytes(s));
  EXPECT_EQ(v.bytes(), voxelBytes(s));
  VoxelVolume iso(test::runtime(), {16, 3, false}, fitVoxelGrid(b, {16, 3, false}));
  EXPECT_EQ(iso.anisotropic(), nullptr);
  EXPECT_THROW(VoxelVolume(test::runtime(), {12, 1, false}, gpu::VoxelGridParams{}), UserError);
  EXPECT_THROW(v.setParams(fitVoxelGrid(b, {16, 2, false})), std::invalid_argument);
}

TEST(VctVolume, InjectAndMipsOnSharedBuffers) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  auto& q = rt.queue();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const VoxelGridSettings s{8, 4, true};
  Aabb b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  VoxelVolume v(rt, s, fitVoxelGrid(b, s));
  std::vector<gpu::VoxelAccum> accum(512, gpu::VoxelAccum{});
  for (auto& a : accum)
    if (rng() % 3 == 0) a = {{unsigned(rng() % 256), unsigned(rng() % 256), unsigned(rng() % 256), 1}, {0, 1024, 0, 0}};
  std::vector<gpu::PointLight> lights;
  for (int i = 0; i < 20; ++i)
    lights.push_back(makeLight({float(rng() % 200) / 100 - 1, 0.9f, float(rng() % 200) / 100 - 1}, 1.5f, glm::vec3(1)));
  v.accum().upload(accum.data(), accum.size() * sizeof(gpu::VoxelAccum));
  cl::Buffer lb = cl::Buffer(rt.context(), CL_MEM_READ_ONLY, lights.size() * sizeof(gpu::PointLight));
  q.enqueueWriteBuffer(lb, CL_TRUE, 0, lights.size() * sizeof(gpu::PointLight), lights.data());

  v.accum().acquireForCl(q, ClAccess::Read);
  v.radiance().acquireForCl(q, ClAccess::Write);
  v.anisotropic()->acquireForCl(q, ClAccess::Write);
  compute::ComputeEnv env(rt);
  VoxelInjector(env).brute(q, v.params(), v.accum().cl(), lb, lights.size(), v.radiance().cl());
  VoxelMips mips(env);
  mips.isotropic(q, v.params(), v.radiance().cl());
  mips.anisotropic(q, v.params(), v.radiance().cl(), v.anisotropic()->cl());
  for (SharedBuffer* sb : {&v.accum(), &v.radiance(), v.anisotropic()}) sb->releaseToGl(q);

  std::vector<F4> want = injectTwin(accum, v.params(), lights);
  want.resize(radianceBytes(s) / 16);
  mipIsotropicTwin(want, s.voxels, s.levels);
  std::vector<F4> want_aniso;
  mipAnisotropicTwin(want, want_aniso, s.voxels, s.levels);
  std::vector<F4> got(want.size()), got_aniso(want_aniso.size());
  v.radiance().download(got.data(), got.size() * 16);
  v.anisotropic()->download(got_aniso.data(), got_aniso.size() * 16);
  // Injection divides and takes square roots: exact only where those are
  // correctly rounded (FpTolerance.hpp); the mips add nothing inexact.
  auto near = [](const F4& a, const F4& w) {
    const float g[4] = {a.x, a.y, a.z, a.w}, e[4] = {w.x, w.y, w.z, w.w};
    for (int c = 0; c < 4; ++c)
      if (!test::floatsMatch(g[c], e[c]) && std::fabs(g[c] - e[c]) > 1e-5f * std::fabs(e[c]) + 1e-7f) return false;
    return true;
  };
  for (std::size_t i = 0; i < want.size(); ++i) ASSERT_TRUE(near(got[i], want[i])) << "radiance voxel " << i;
  for (std::size_t i = 0; i < want_aniso.size(); ++i) ASSERT_TRUE(near(got_aniso[i], want_aniso[i])) << "aniso " << i;
  bool lit = false;
  for (std::size_t i = 0; i < 512; ++i) lit |= got[i].x > 0;
  EXPECT_TRUE(lit) << "no voxel lit: the comparison would prove nothing";
}

}  // namespace
}  // namespace ml::vct
