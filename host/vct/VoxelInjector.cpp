#include "host/vct/VoxelInjector.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/cl/Launch.hpp"
#include "host/compute/FittedProgram.hpp"
#include "host/compute/HostIo.hpp"
#include "host/vct/VoxelGrid.hpp"

namespace ml::vct {


VoxelInjector::VoxelInjector(const compute::ComputeEnv& env, const compute::Options& options, bool shadows,
                             bool skip_empty)
    : env_(env),
      tuning_(compute::resolveTuning(env, options)),
      shadows_(shadows),
      skip_(shadows && skip_empty),
      own_(env, options),
      boxes_(env.context(), CL_MEM_READ_ONLY, kMaxRegionBoxes * 2 * sizeof(cl_uint4)) {}

void VoxelInjector::build() {
  if (brute_()) return;
  // GPU shape: the group size the compiled kernels accept on this device.
  const compute::FittedProgram fitted =
      compute::buildFitted(env_, tuning_, "vct/vct_inject.cl", "voxel injection", [this](std::size_t) {
        return Defines{{"VCT_SHADOWS", shadows_ ? "1" : "0"}, {"VCT_SHADOW_SKIP", skip_ ? "1" : "0"}};
      });
  tuning_.wg = fitted.wg;
  const cl::Program& p = fitted.program;
  brute_ = cl::Kernel(p, "inject_brute");
  hashed_ = cl::Kernel(p, "inject_hashed");
  if (shadows_) probe_ = cl::Kernel(p, "visibility_probe");
}

const cl::Buffer& VoxelInjector::occupancyFor(cl::CommandQueue& q, const gpu::VoxelGridParams& g,
                                              const cl::Buffer& accum, ClPassTimer* timer,
                                              const VoxelOccupancy* occupancy) {
  if (!skip_) return accum;
  if (!occupancy) {
    own_.build(q, g.edge, accum, timer);
    occupancy = &own_;
  }
  if (occupancy->edge() != g.edge)
    throw std::invalid_argument("VoxelInjector: the occupancy was built for another grid edge");
  return occupancy->buffer();
}

std::size_t VoxelInjector::prepare(cl::Kernel& k, cl::CommandQueue& q, const gpu::VoxelGridParams& g,
                                   const cl::Buffer& accum, const cl::Buffer& lights, std::size_t light_count,
                                   cl::Buffer& radiance, std::size_t& local, ClPassTimer* timer,
                                   const VoxelOccupancy* occupancy, const VoxelRegion& region) {
  VoxelGridSettings s;
  s.voxels = g.edge;
  s.levels = g.levels;
  checkVoxelGrid(s);
  const std::size_t n = std::size_t(g.edge) * g.edge * g.edge;
  requireBuffer(accum, n * sizeof(gpu::VoxelAccum), "VoxelInjector accumulation buffer");
  requireBuffer(radiance, n * 16, "VoxelInjector radiance volume");
  requireBuffer(lights, light_count * sizeof(gpu::PointLight), "VoxelInjector lights");
  requireCount(light_count, "VoxelInjector lights");
  checkRegion(region, g.edge);
  if (shadows_ && g.wrap) throw std::invalid_argument("VoxelInjector: shadows need an unscrolled grid (wrap 0)");
  build();
  std::vector<cl_uint4> boxes;
  for (const VoxelBox& b : region) {
    boxes.push_back(cl_uint4{{b.lo[0], b.lo[1], b.lo[2], 0u}});
    boxes.push_back(cl_uint4{{b.hi[0], b.hi[1], b.hi[2], 0u}});
  }
  if (!boxes.empty()) q.enqueueWriteBuffer(boxes_, CL_TRUE, 0, boxes.size() * sizeof(cl_uint4), boxes.data());
  std::size_t chunk = 1, global = n;
  local = tuning_.wg;
  if (!tuning_.gpu()) {
    // A filled voxel costs a whole light loop, so the chunk floor is 64
    // voxels, not the primitives' 4096: a 16^3 grid is still split among all
    // work-items (tuning().chunks of them at most) and PoCL's threads.
    chunk = tuning_.cpuChunk(n, 64);
    // Where the device ends a work-item's loops after 65,535 iterations in
    // total (llvmpipe; Tuning::max_chunk is set there,
    // tests/driver/driver_loop_cap_test.cpp), a voxel per work-item, as in the GPU
    // shape: one voxel's light loop (with shadows, times its marches) is the
    // least a work-item can take, and a chunk of them passed the cap with a
    // few hundred lights.
    if (tuning_.max_chunk) chunk = 1;
    global = ceilDiv(n, chunk);
    local = 1;
  }
  const auto& o = g.origin_voxel_size;
  const gpu::VoxelCorner c = gpu::voxel_corner(g);
  setArgs(k, accum, occupancyFor(q, g, accum, timer, occupancy), radiance, cl_float4{{o.x, o.y, o.z, o.w}},
          cl_uint(log2Exact(g.edge)), cl_int4{{c.x, c.y, c.z, g.wrap ? 1 : 0}}, boxes_, u32(region.size()), u32(n),
          u32(chunk), lights);
  return global;
}

void VoxelInjector::brute(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                          const cl::Buffer& lights, std::size_t light_count, cl::Buffer& radiance,
                          ClPassTimer* timer, const VoxelOccupancy* occupancy, const VoxelRegion& region) {
  std::size_t local = 1;
  const std::size_t global =
      prepare(brute_, q, g, accum, lights, light_count, radiance, local, timer, occupancy, region);
  brute_.setArg(kArgLights + 1, u32(light_count));
  launchTimed(q, brute_, global, local, timer, "vct-inject");
}

void VoxelInjector::hashed(cl::CommandQueue& q, const gpu::VoxelGridParams& g, const cl::Buffer& accum,
                           const cl::Buffer& lights, std::size_t light_count, const HashedListsCl& lists,
                           cl::Buffer& radiance, ClPassTimer* timer, const VoxelOccupancy* occupancy,
                           const VoxelRegion& region) {
  std::size_t local = 1;
  const std::size_t global =
      prepare(hashed_, q, g, accum, lights, light_count, radiance, local, timer, occupancy, region);
  lists.setArgs(hashed_, kArgLights + 1);
  launchTimed(q, hashed_, global, local, timer, "vct-inject");
}

std::vector<VoxelInjector::MarchResult> VoxelInjector::march(cl::CommandQueue& q, const gpu::VoxelGridParams& g,
                                                             const cl::Buffer& accum,
                                                             const std::vector<gpu::ml_float4>& pn,
                                                             const std::vector<gpu::ml_float4>& lp) {
  if (!shadows_) throw std::logic_error("VoxelInjector::march: built without shadows");
  if (pn.size() != 2 * lp.size()) throw std::invalid_argument("VoxelInjector::march: pn needs two float4 per query");
  const std::size_t n = lp.size();
  requireBuffer(accum, std::size_t(g.edge) * g.edge * g.edge * sizeof(gpu::VoxelAccum),
                               "VoxelInjector accumulation buffer");
  build();
  const auto& o = g.origin_voxel_size;
  // Empty inputs still need buffers: an OpenCL buffer needs a size.
  const auto padded = [](std::vector<gpu::ml_float4> v) { return v.empty() ? std::vector<gpu::ml_float4>(1) : v; };
  cl::Buffer pnb = compute::upload(env_.context(), q, padded(pn)), lpb = compute::upload(env_.context(), q, padded(lp));
  cl::Buffer out(env_.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(n, 1) * 8);
  compute::poison(q, out);
  setArgs(probe_, accum, occupancyFor(q, g, accum, nullptr, nullptr), cl_float4{{o.x, o.y, o.z, o.w}},
                           cl_uint(log2Exact(g.edge)), pnb, lpb, u32(n), out);
  if (n) launchTimed(q, probe_, n, 1, nullptr, "");
  const auto words = compute::download<cl_uint>(q, out, 2 * n);
  std::vector<MarchResult> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = {words[2 * i] != 0, words[2 * i + 1]};
  return r;
}

}  // namespace ml::vct
