#include "host/vct/VctPipeline.hpp"

#include <algorithm>
#include <chrono>

#include "gl/GlPassTimer.hpp"

namespace ml::vct {

VctPipeline::VctPipeline(ClRuntime& rt, const VctPipelineOptions& options, const Aabb& scene_bounds)
    : rt_(rt),
      options_(options),
      env_(rt),
      volume_(rt, options.grid, fitVoxelGrid(scene_bounds, options.grid)),
      injector_(env_, options.compute, options.shadows),
      occupancy_(env_, options.compute),
      mips_(env_, options.compute),
      lists_(env_),
      hashed_(hashed::HashedConfig{}) {}

void VctPipeline::update(const SceneGpu& scene, const std::vector<gpu::PointLight>& lights, PassTimings& timings) {
  if (voxelizations_ == 0 || options_.revoxelize) {
    GlPassTimer gl_timer;
    voxelize_.run(scene, volume_.params(), volume_.accum(), &gl_timer);
    gl_timer.collect(timings);
    ++voxelizations_;
    occupancy_stale_ = true;
  }
  cl::CommandQueue& q = rt_.queue();
  ClPassTimer timer;
  volume_.accum().acquireForCl(q, ClAccess::Read);
  volume_.radiance().acquireForCl(q, ClAccess::ReadWrite);
  if (volume_.anisotropic()) volume_.anisotropic()->acquireForCl(q, ClAccess::Write);
  if (options_.shadows && occupancy_stale_) {
    occupancy_.build(q, volume_.params().edge, volume_.accum().cl(), &timer);
    occupancy_stale_ = false;
  }
  inject(q, lights, timings, timer);
  mips(q, timer);
  timer.collect(timings);
  if (volume_.anisotropic()) volume_.anisotropic()->releaseToGl(q);
  volume_.radiance().releaseToGl(q);
  volume_.accum().releaseToGl(q);
  unpackTextures(timings);
  ++updates_;
}

void VctPipeline::refilter(PassTimings& timings) {
  cl::CommandQueue& q = rt_.queue();
  ClPassTimer timer;
  volume_.radiance().acquireForCl(q, ClAccess::ReadWrite);
  if (volume_.anisotropic()) volume_.anisotropic()->acquireForCl(q, ClAccess::Write);
  mips(q, timer);
  timer.collect(timings);
  if (volume_.anisotropic()) volume_.anisotropic()->releaseToGl(q);
  volume_.radiance().releaseToGl(q);
  unpackTextures(timings);
}

void VctPipeline::mips(cl::CommandQueue& q, ClPassTimer& timer) {
  mips_.isotropic(q, volume_.params(), volume_.radiance().cl(), &timer);
  if (volume_.anisotropic())
    mips_.anisotropic(q, volume_.params(), volume_.radiance().cl(), volume_.anisotropic()->cl(), &timer);
}

void VctPipeline::unpackTextures(PassTimings& timings) {
  GlPassTimer gl_timer;
  textures_.unpack(volume_.params(), volume_.radiance().gl(), volume_.anisotropic() ? volume_.anisotropic()->gl() : 0,
                   &gl_timer);
  gl_timer.collect(timings);
}

// Lights go to a grown device buffer (never empty: an OpenCL buffer needs a
// size); without lights the hashed structure has nothing to bound, and brute
// force over zero lights writes the unlit volume.
void VctPipeline::inject(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights, PassTimings& timings,
                         ClPassTimer& timer) {
  const std::size_t bytes = std::max<std::size_t>(lights.size(), 1) * sizeof(gpu::PointLight);
  if (bytes > lights_capacity_) {
    lights_ = cl::Buffer(env_.context(), CL_MEM_READ_ONLY, bytes);  // the runtime's CL calls throw on error
    lights_capacity_ = bytes;
  }
  if (!lights.empty())
    q.enqueueWriteBuffer(lights_, CL_TRUE, 0, lights.size() * sizeof(gpu::PointLight), lights.data());
  const gpu::VoxelGridParams& g = volume_.params();
  if (options_.brute_force || lights.empty()) {
    injector_.brute(q, g, volume_.accum().cl(), lights_, lights.size(), volume_.radiance().cl(), &timer, occupancy());
    return;
  }
  // The first update builds; later ones update incrementally
  // (HashedStructure::update, which rebuilds by itself when that is cheaper
  // or the lights left the octree) and upload only what changed.
  const auto start = std::chrono::steady_clock::now();
  const hashed::UpdateStats& st = hashed_.update(lights);
  lists_.upload(q, hashed_.linkless(), st.full_rebuild);
  ++(st.full_rebuild ? list_builds_ : list_updates_);
  if (!st.full_rebuild) list_update_bytes_ += lists_.lastUploadBytes();
  timings.add("vct-lists", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  injector_.hashed(q, g, volume_.accum().cl(), lights_, lights.size(), lists_, volume_.radiance().cl(), &timer,
                   occupancy());
}

}  // namespace ml::vct
