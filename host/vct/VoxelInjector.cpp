#include "host/vct/VoxelInjector.hpp"

#include "host/compute/Detail.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {

using compute::detail::u32;

VoxelInjector::VoxelInjector(const compute::ComputeEnv& env, const compute::Options& options, bool shadows)
    : env_(env), tuning_(compute::resolveTuning(env, options)), shadows_(shadows) {}

std::size_t VoxelInjector::prepare(cl::Kernel& k, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                                   const cl::Buffer& lights, std::size_t light_count, cl::Buffer& radiance,
                                   std::size_t& local) {
  VoxelGridSettings s;
  s.voxels = g.edge;
  s.levels = g.levels;
  checkVoxelGrid(s);
  const std::size_t n = std::size_t(g.edge) * g.edge * g.edge;
  compute::detail::checkBuffer(accum, n * sizeof(gpu::VoxelAccum), "VoxelInjector accumulation buffer");
  compute::detail::checkBuffer(radiance, n * 16, "VoxelInjector radiance volume");
  compute::detail::checkBuffer(lights, light_count * sizeof(gpu::PointLight), "VoxelInjector lights");
  compute::detail::checkCount(light_count, "VoxelInjector lights");
  if (!brute_()) {
    cl::Program p = compute::detail::buildShaped(env_, tuning_, "vct_inject.cl", {{"VCT_SHADOWS", shadows_ ? "1" : "0"}});
    brute_ = cl::Kernel(p, "inject_brute");
    hashed_ = cl::Kernel(p, "inject_hashed");
  }
  std::size_t chunk = 1, global = n;
  local = tuning_.wg;
  if (!tuning_.gpu()) {
    // A filled voxel costs a whole light loop, so the chunk floor is 64
    // voxels, not the primitives' 4096: a 16^3 grid is still split among all
    // work-items (tuning().chunks of them at most) and PoCL's threads.
    chunk = tuning_.cpuChunk(n, 64);
    global = compute::detail::ceilDiv(n, chunk);
    local = 1;
  }
  const auto& o = g.origin_voxel_size;
  compute::detail::setArgs(k, accum, radiance, cl_float4{{o.x, o.y, o.z, o.w}}, cl_uint(log2Exact(g.edge)), u32(n),
                           u32(chunk), lights);
  return global;
}

void VoxelInjector::brute(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                          const cl::Buffer& lights, std::size_t light_count, cl::Buffer& radiance,
                          ClPassTimer* timer) {
  std::size_t local = 1;
  const std::size_t global = prepare(brute_, g, accum, lights, light_count, radiance, local);
  brute_.setArg(7, u32(light_count));
  compute::detail::launch(q, brute_, global, local, timer, "vct-inject");
}

void VoxelInjector::hashed(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                           const cl::Buffer& lights, std::size_t light_count, const HashedListsCl& lists,
                           cl::Buffer& radiance, ClPassTimer* timer) {
  std::size_t local = 1;
  const std::size_t global = prepare(hashed_, g, accum, lights, light_count, radiance, local);
  lists.setArgs(hashed_, 7);
  compute::detail::launch(q, hashed_, global, local, timer, "vct-inject");
}

}  // namespace ml::vct
