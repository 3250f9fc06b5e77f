// The VCT mip cases of the kernel bench (kernel_bench_cases.hpp): isotropic
// and anisotropic mip propagation (host/vct/VoxelMips.hpp) of a random level
// 0, checked bit for bit against the C++ twins (VoxelMipsReference.hpp).
// bytes counts what the mips read and write (8 children per parent voxel, six
// direction sets for the anisotropic volume), as manylights-vct-bench does.
#include <algorithm>
#include <cstring>
#include <memory>
#include <random>

#include "MipTraffic.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/HostIo.hpp"
#include "host/vct/VoxelMips.hpp"
#include "host/vct/VoxelMipsReference.hpp"
#include "kernel_bench_cases.hpp"

namespace ml::kbench {

using compute::download;

namespace {

double mipBytes(unsigned edge, unsigned levels, bool aniso) { return ml::bench::mipTrafficBytes(edge, levels, aniso); }

struct VolumeInputs {
  VolumeInputs(Bench& b, unsigned edge, unsigned levels)
      : grid{{0, 0, 0, 1}, edge, levels, 0, 0}, mips(compute::ComputeEnv(b.rt), b.tune) {
    std::mt19937 rng(edge * 31 + levels);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    level0.resize(gpu::voxel_level_offset(edge, levels));
    const std::size_t n0 = std::size_t(edge) * edge * edge;
    for (std::size_t i = 0; i < level0.size(); ++i)
      level0[i] = i < n0 ? gpu::ml_float4{u(rng), u(rng), u(rng), u(rng)} : gpu::ml_float4{0, 0, 0, 0};
    volume = compute::upload(b.rt.context(), b.q, level0);
    aniso = cl::Buffer(b.rt.context(), CL_MEM_READ_WRITE,
                       std::max<std::size_t>(gpu::voxel_aniso_index(edge, levels, 0, 0), 1) * 16);
  }
  gpu::VoxelGridParams grid;
  vct::VoxelMips mips;
  std::vector<gpu::ml_float4> level0;  // level 0 random, the other levels zero
  cl::Buffer volume, aniso;
};

VolumeInputs& volume(Bench& b, unsigned edge, unsigned levels) {
  return b.slot.get<VolumeInputs>({2, std::size_t(edge) * 64 + levels},
                                  [&] { return std::make_unique<VolumeInputs>(b, edge, levels); });
}

// Levels 1.. (isotropic) or the whole anisotropic volume to 0xDEADBEEF words.
void poisonOutputs(Bench& b, VolumeInputs& v) {
  const std::size_t first = std::size_t(v.grid.edge) * v.grid.edge * v.grid.edge * 16;
  const std::size_t total = v.level0.size() * 16;
  if (total > first) b.q.enqueueFillBuffer(v.volume, cl_uint(0xDEADBEEFu), first, total - first);
  b.q.enqueueFillBuffer(v.aniso, cl_uint(0xDEADBEEFu), 0, v.aniso.getInfo<CL_MEM_SIZE>() / 4 * 4);
  b.q.finish();
}

std::string firstFloatDifference(const std::string& what, const std::vector<gpu::ml_float4>& got,
                                 const std::vector<gpu::ml_float4>& want) {
  for (std::size_t i = 0; i < want.size(); ++i)
    if (std::memcmp(&got[i], &want[i], sizeof want[i]) != 0)
      return what + ": float4 " + std::to_string(i) + " is (" + std::to_string(got[i].x) + ", " +
             std::to_string(got[i].y) + ", " + std::to_string(got[i].z) + ", " + std::to_string(got[i].w) +
             "), expected (" + std::to_string(want[i].x) + ", " + std::to_string(want[i].y) + ", " +
             std::to_string(want[i].z) + ", " + std::to_string(want[i].w) + ")";
  return "";
}

std::string checkMips(Bench& b, unsigned edge, unsigned levels, bool an) {
  VolumeInputs& v = volume(b, edge, levels);
  std::vector<gpu::ml_float4> want = v.level0;
  if (!an) {
    vct::mipIsotropicTwin(want, edge, levels);
    return firstFloatDifference("isotropic mips", download<gpu::ml_float4>(b.q, v.volume, want.size()), want);
  }
  std::vector<gpu::ml_float4> aniso;
  vct::mipAnisotropicTwin(want, aniso, edge, levels);
  return firstFloatDifference("anisotropic mips", download<gpu::ml_float4>(b.q, v.aniso, aniso.size()), aniso);
}

}  // namespace

void addVctCases(Bench& b, unsigned edge, unsigned levels) {
  const std::size_t voxels = std::size_t(edge) * edge * edge;
  for (const bool an : {false, true}) {
    b.h.add(Case(an ? "vct_mips.anisotropic" : "vct_mips.isotropic", voxels, mipBytes(edge, levels, an))
                .before([&b, edge, levels] { poisonOutputs(b, volume(b, edge, levels)); })
                .run([&b, edge, levels, an] {
                  VolumeInputs& v = volume(b, edge, levels);
                  an ? v.mips.anisotropic(b.q, v.grid, v.volume, v.aniso) : v.mips.isotropic(b.q, v.grid, v.volume);
                })
                .checkedBy([&b, edge, levels, an] { return checkMips(b, edge, levels, an); })
                .profiledBy([&b, edge, levels, an](ClPassTimer& t) {
                  VolumeInputs& v = volume(b, edge, levels);
                  an ? v.mips.anisotropic(b.q, v.grid, v.volume, v.aniso, &t)
                     : v.mips.isotropic(b.q, v.grid, v.volume, &t);
                }));
  }
}

}  // namespace ml::kbench
