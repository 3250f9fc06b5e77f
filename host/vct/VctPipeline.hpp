#pragma once
// One voxel cone tracing update per frame, on one VoxelVolume:
//   voxelize (GL, gl/VoxelizePass) -> inject (OpenCL, VoxelInjector) -> mips
//   (OpenCL, VoxelMips: isotropic, plus anisotropic when the settings ask).
// Static geometry is voxelized on the first update only; `revoxelize` redoes
// it every update (moving geometry). With shadows, each voxelization is
// followed by the distance volume the shadow march skips empty space with
// (VoxelOccupancy, CL device time `vct-occupancy`). Inject and mips rerun
// every update, so a light move costs only those two. Injection looks lights
// up in the hashed structure's lists unless `brute_force` is set: this
// pipeline's own HashedStructure (no geometry mask), built over the first
// update's lights, then updated incrementally (DynamicLightUpdater) with each
// update's lights, and copied to OpenCL buffers by HashedListsCl, which after
// an update writes only what it changed (hashed::GpuUploadPlan); host time
// `vct-lists`.
// Hand-overs: the volume's SharedBuffers are acquired for CL after the GL
// voxelization and released to GL after the mips (GL owns them between
// updates), then unpacked into mip-mapped 3D textures for sampling
// (gl/VoxelTextures). Passes: `vct-voxelize` (GL), `vct-inject`, `vct-mips`
// (CL device times), `vct-textures` (GL), added to the caller's PassTimings.
// Not thread-safe; needs the current GL context of the scene's SceneGpu.
#include <cstddef>
#include <memory>
#include <vector>

#include "gl/SceneGpu.hpp"
#include "host/vct/VoxelTextures.hpp"
#include "host/vct/VoxelizePass.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/hashed/HashedStructure.hpp"
#include "host/util/PassTimings.hpp"
#include "host/vct/HashedListsCl.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "host/vct/VoxelInjector.hpp"
#include "host/vct/VoxelMips.hpp"
#include "host/vct/VoxelOccupancy.hpp"
#include "host/vct/VoxelVolume.hpp"

namespace ml::vct {

struct VctPipelineOptions {
  VoxelGridSettings grid;
  bool revoxelize = false;   // moving geometry: voxelize on every update
  bool brute_force = false;  // inject from every light instead of the hashed lists
  bool shadows = false;      // --vct-shadows voxel: visibility through level-0 opacity (VoxelInjector)
  compute::Options compute;  // kernel shape of inject and mips
};

class VctPipeline {
 public:
  // The grid is fitted around `scene_bounds` (fitVoxelGrid; UserError for bad
  // settings, naming the flag).
  VctPipeline(ClRuntime& rt, const VctPipelineOptions& options, const Aabb& scene_bounds);

  void update(const SceneGpu& scene, const std::vector<gpu::PointLight>& lights, PassTimings& timings);
  // After a GL pass rewrote level 0 of the radiance volume (VoxelBouncePass):
  // the mips and the textures again, added to `vct-mips` and `vct-textures`.
  void refilter(PassTimings& timings);

  VoxelVolume& volume() { return volume_; }
  const VoxelVolume& volume() const { return volume_; }
  const VoxelTextures& textures() const { return textures_; }
  std::size_t voxelizations() const { return voxelizations_; }  // tests: static geometry once
  std::size_t updates() const { return updates_; }
  // The hashed lists: full builds, incremental updates, the last upload's
  // bytes and the bytes uploaded by all incremental updates.
  std::size_t listBuilds() const { return list_builds_; }
  std::size_t listUpdates() const { return list_updates_; }
  std::size_t lastListUploadBytes() const { return lists_.lastUploadBytes(); }
  std::size_t listUpdateBytes() const { return list_update_bytes_; }
  const hashed::HashedStructure& lists() const { return hashed_; }

 private:
  void inject(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights, PassTimings& timings,
              ClPassTimer& timer);
  void mips(cl::CommandQueue& q, ClPassTimer& timer);
  void unpackTextures(PassTimings& timings);
  const VoxelOccupancy* occupancy() const { return options_.shadows ? &occupancy_ : nullptr; }
  bool occupancy_stale_ = true;  // voxelized since the occupancy was built

  ClRuntime& rt_;
  VctPipelineOptions options_;
  compute::ComputeEnv env_;
  VoxelVolume volume_;
  VoxelizePass voxelize_;
  VoxelTextures textures_;
  VoxelInjector injector_;
  VoxelOccupancy occupancy_;  // of the last voxelization, for the shadow march
  VoxelMips mips_;
  HashedListsCl lists_;
  hashed::HashedStructure hashed_;
  cl::Buffer lights_;
  std::size_t lights_capacity_ = 0;
  std::size_t voxelizations_ = 0, updates_ = 0, list_builds_ = 0, list_updates_ = 0, list_update_bytes_ = 0;
};

}  // namespace ml::vct
