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
// (gl/VoxelTextures). Passes: `vct-voxelize` (GL), `vct-inject`, `vct-fold`
// (--vct-fold), `vct-mips` (CL device times), `vct-textures` (GL), added to
// the caller's PassTimings.
// Cascades (options.cascades = L > 1, VoxelCascade.hpp): L volumes, the
// outermost the grid around the scene, the inner ones toroidal and centred
// on the update's eye. A level the eye moved voxelizes and injects only the
// slabs that scrolled in (VoxelRegion; the rest of its level 0 keeps its
// place), then its mips and textures run again; a light change injects every
// level. With options.fold (--vct-fold) mips run across levels too
// (CascadeFold): finest first, each coarser level's level 0 takes the finer
// level's opacity where the finer window lies, before its own mips; where
// the finer window moved away, the coarser level is injected again from its
// own voxelization. The hashed lists serve every level. Shadows and
// refilter() need L = 1.
// Not thread-safe; needs the current GL context of the scene's SceneGpu.
#include <glm/glm.hpp>

#include <cstddef>
#include <memory>
#include <vector>

#include "gl/SceneGpu.hpp"
#include "host/vct/CascadeFold.hpp"
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
#include "host/vct/VoxelCascade.hpp"
#include "host/vct/VoxelVolume.hpp"

namespace ml::vct {

struct VctPipelineOptions {
  VoxelGridSettings grid;
  bool revoxelize = false;   // moving geometry: voxelize on every update
  bool brute_force = false;  // inject from every light instead of the hashed lists
  bool shadows = false;      // --vct-shadows voxel: visibility through level-0 opacity (VoxelInjector)
  unsigned cascades = 1;     // --vct-cascades
  bool fold = false;         // --vct-fold: mips across cascade levels (CascadeFold)
  compute::Options compute;  // kernel shape of inject and mips
};

// What changed since the last update: where the camera is (cascades follow
// it) and whether the lights are new (every level is injected again).
struct VctUpdateInputs {
  glm::vec3 eye{0.0f};
  bool lights_changed = true;
};

// What the last update did: levels voxelized in full, levels scrolled and
// the level-0 voxels voxelized and injected again for the scroll; level-0
// voxels injected again for the fold (the box around the cells a finer
// window covered and covers; not counted above) and those folded from finer
// levels (CascadeFold).
struct VctUpdateReport {
  unsigned full_levels = 0, scrolled_levels = 0;
  std::size_t scrolled_voxels = 0, refolded_voxels = 0, folded_voxels = 0;
};

// A box of lattice cells of a level's voxel size (hi exclusive; empty when any hi <= lo).
struct LatticeBox {
  long long lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool empty() const { return hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]; }
  bool operator==(const LatticeBox& o) const;
};

// One level of the cascade: its volume and textures.
struct CascadeLevel {
  CascadeLevel(ClRuntime& rt, const VoxelGridSettings& s, const gpu::VoxelGridParams& p) : volume(rt, s, p) {}
  VoxelVolume volume;
  VoxelTextures textures;
  bool placed = false;  // voxelized at volume.params()
  LatticeBox folded;    // the cells of level 0 that hold the finer level's mip (CascadeFold)
};

class VctPipeline {
 public:
  // The grid is fitted around `scene_bounds` (fitVoxelGrid; UserError for bad
  // settings, naming the flag).
  VctPipeline(ClRuntime& rt, const VctPipelineOptions& options, const Aabb& scene_bounds);

  void update(const SceneGpu& scene, const std::vector<gpu::PointLight>& lights, PassTimings& timings,
              const VctUpdateInputs& in = {});
  // After a GL pass rewrote level 0 of the radiance volume (VoxelBouncePass):
  // the mips and the textures again, added to `vct-mips` and `vct-textures`.
  void refilter(PassTimings& timings);
  // Whether a camera at `eye` would move a level (an update is due).
  bool moves(const glm::vec3& eye) const;
  const VctUpdateReport& lastUpdate() const { return report_; }

  // The outermost level (the only one without cascades) and level c (0 finest).
  VoxelVolume& volume() { return levels_.back()->volume; }
  const VoxelVolume& volume() const { return levels_.back()->volume; }
  const VoxelTextures& textures() const { return levels_.back()->textures; }
  unsigned cascades() const { return static_cast<unsigned>(levels_.size()); }
  bool folds() const { return options_.fold && cascades() > 1; }
  CascadeLevel& level(unsigned c) { return *levels_.at(c); }
  const CascadeLevel& level(unsigned c) const { return *levels_.at(c); }
  std::size_t bytes() const;  // every level's volume
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
  // Voxelizes what moved; returns per level whether it changed and the
  // region to inject (empty: all).
  void voxelize(const SceneGpu& scene, const glm::vec3& eye, PassTimings& timings, std::vector<bool>& touched,
                std::vector<VoxelRegion>& regions);
  void uploadLights(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights, PassTimings& timings);
  void lightLevel(cl::CommandQueue& q, CascadeLevel& l, std::size_t light_count, const VoxelRegion& region,
                  ClPassTimer& timer);
  void mips(cl::CommandQueue& q, VoxelVolume& v, ClPassTimer& timer);
  // What level c must do this update: whether it runs at all, whether it is
  // injected and where (an empty region: all of it).
  struct LevelWork {
    bool run = false, inject = false;
    VoxelRegion region;
  };
  LevelWork levelWork(unsigned c, bool relight, bool touched, const VoxelRegion& scrolled, bool finer_changed);
  void fold(cl::CommandQueue& q, unsigned c, ClPassTimer& timer);
  void unpackTextures(CascadeLevel& l, PassTimings& timings);
  const VoxelOccupancy* occupancy() const { return options_.shadows ? &occupancy_ : nullptr; }
  bool occupancy_stale_ = true;  // voxelized since the occupancy was built

  ClRuntime& rt_;
  VctPipelineOptions options_;
  Aabb bounds_;
  compute::ComputeEnv env_;
  std::vector<std::unique_ptr<CascadeLevel>> levels_;
  VoxelizePass voxelize_;
  VoxelInjector injector_;
  VoxelOccupancy occupancy_;  // of the last voxelization, for the shadow march
  VoxelMips mips_;
  CascadeFold fold_;
  HashedListsCl lists_;
  hashed::HashedStructure hashed_;
  cl::Buffer lights_;
  std::size_t lights_capacity_ = 0;
  bool lists_valid_ = false;  // the hashed lists hold the current lights
  VctUpdateReport report_;
  std::size_t voxelizations_ = 0, updates_ = 0, list_builds_ = 0, list_updates_ = 0, list_update_bytes_ = 0;
};

}  // namespace ml::vct
