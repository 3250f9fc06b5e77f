#pragma once
// Voxel cone tracing as the frame's GI pass (gl/GiPass.hpp), whatever
// technique lit the frame:
//   update():      VctPipeline::update (voxelize once, inject from the frame's
//                  lights, mips, 3D textures) when the volume is stale: on the
//                  first frame, when the lights are not the ones of the last
//                  update (GiSceneInputs::lights_version differs or is 0), and
//                  on every frame with `revoxelize` (moving geometry: it
//                  voxelizes first, and the rest follows). Otherwise the last
//                  volume is reused as it is (bit for bit what an update would
//                  write: same scene, lights and settings), its passes do not
//                  run and do not appear in the frame's PassTimings (as the
//                  hashed technique's skipped update). The settings are fixed
//                  for the pass's life (the viewer builds a new pass on any
//                  change) and the volume does not depend on the resolution;
//                  the hashed lists follow moved lights incrementally.
//                  With cascades, a frame whose camera moves a level updates
//                  too: the scrolled slabs only (VctPipeline);
//   addIndirect(): `vct-trace` (gl/shaders/vct/vct_trace.comp: diffuse cones, the
//                  ambient occlusion and, with `specular`, a specular cone, at
//                  gi_scale of the frame's resolution) and `vct-upsample`
//                  (vct_upsample.comp: depth/normal-aware to full resolution,
//                  times the G-buffer albedo, added to the shaded image).
// Transport: the volume holds the direct light of the renderer's model without
// visibility (`--vct-shadows none`) or with each light's visibility through
// level-0 opacity (`--vct-shadows voxel`, VoxelInjector), times its
// 0.9 direct weight; the indirect image follows host/reference/IndirectReference
// (bounce light without that weight), hence a 1/0.9 scale, so that it is
// compared with the reference as is. The specular cone adds
// kSpecularWeight x its radiance (a dielectric coat, F0 0.04, aperture 10 deg).
// stats() (VctGiPassReport.cpp): the settings, the voxel memory, the
// updates, reuses and list uploads for render's printout and stats JSON;
// extraImages(): the ambient occlusion ("ao"); view(): the voxel volume as
// cubes or a slice (VoxelView), drawn by a VoxelViewPass made on first use.
// checkVctGiSettings(): UserError with one line naming the flag.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gl/GiPass.hpp"
#include "host/vct/ConeTracing.hpp"
#include "host/vct/VctPipeline.hpp"
#include "host/vct/VoxelBouncePass.hpp"
#include "host/vct/VoxelView.hpp"

namespace ml::vct {

inline constexpr float kSpecularWeight = 0.04f;
inline constexpr float kSpecularApertureDeg = 10.0f;
inline constexpr unsigned kMaxVctBounces = 2;  // --gi-bounces

struct VctGiSettings {
  VoxelGridSettings grid;   // --voxels, --levels, --anisotropic
  unsigned cones = 9;       // --cones
  float aperture_deg = 45;  // --cone-aperture
  float lod_bias = kConeLodBias;  // --cone-lod-bias
  float gi_scale = 0.5f;    // --gi-scale: trace resolution / frame resolution, (0, 1]
  bool specular = false;    // --specular
  std::string shadows = "none";  // --vct-shadows: none | voxel (visibility through level-0 opacity)
  bool revoxelize = false;       // --revoxelize: voxelize every frame (moving geometry), not only the first
  unsigned bounces = 1;          // --gi-bounces: 1, or 2 (each voxel gathers once more: VoxelBouncePass)
  unsigned cascades = 1;         // --vct-cascades: levels of the camera-centred cascade (VoxelCascade.hpp)
  bool fold = false;             // --vct-fold: mips across the cascade's levels (CascadeFold.hpp)
  bool brute_inject = false;     // inject from every light instead of the hashed lists
  ConeBreak broken = ConeBreak::None;  // tests only
};

void checkVctGiSettings(const VctGiSettings& s);

class VctGiPass final : public GiPass {
 public:
  VctGiPass(ClRuntime& rt, const VctGiSettings& s, const Aabb& scene_bounds);
  ~VctGiPass() override;
  VctGiPass(const VctGiPass&) = delete;
  VctGiPass& operator=(const VctGiPass&) = delete;

  void update(const GiSceneInputs& in) override;
  void addIndirect(const GiFrameInputs& in) override;
  std::vector<float> indirectRgba() const override;
  std::size_t memoryBytes() const override;  // voxel volumes (voxelBytes) + textures + images
  GiUpdateCounts updateCounts() const override { return {volumeUpdates(), volumeReuses()}; }
  GiStats stats() const override;
  std::vector<GiImage> extraImages() const override;
  GiViewImage view(const ParamValues& view, const GiViewInputs& in) override;
  std::vector<float> ambientOcclusion() const;  // last frame, one float per pixel, 0 on the sky
  const VctGiSettings& settings() const { return s_; }
  const VctPipeline& pipeline() const { return pipeline_; }  // the voxel volume, for debug views
  // Frames whose update() ran the pipeline (pipeline().updates()) and frames
  // that reused the last volume.
  std::size_t volumeUpdates() const { return pipeline_.updates(); }
  std::size_t volumeReuses() const { return reuses_; }

 private:
  bool volumeStale(const GiSceneInputs& in) const;
  ConeTraceSetup coneSetup() const;
  void allocate(unsigned width, unsigned height);
  void freeImages();
  void trace(const GiFrameInputs& in);
  void upsample(const GiFrameInputs& in);

  VctGiSettings s_;
  VctPipeline pipeline_;
  std::vector<Cone> cones_;
  float cone_turn_;  // coneSetTurn of cones_, vct_trace.comp's u_cone_turn
  ShaderProgram trace_, upsample_;
  unsigned width_ = 0, height_ = 0, lo_w_ = 0, lo_h_ = 0;
  std::uint64_t volume_lights_ = 0;  // lights_version of the last update; 0: none yet
  std::size_t reuses_ = 0;
  std::size_t scrolls_ = 0, scrolled_voxels_ = 0;  // cascade levels scrolled, voxels they redid
  std::unique_ptr<VoxelViewPass> voxel_view_;  // made by the first view()
  std::unique_ptr<VoxelBouncePass> bounce_;    // with bounces > 1
  GLuint lo_irradiance_ = 0, lo_geometry_ = 0, lo_specular_ = 0, indirect_ = 0, ao_ = 0;
};

}  // namespace ml::vct
