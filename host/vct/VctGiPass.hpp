#pragma once
// Voxel cone tracing as the frame's GI pass (gl/GiPass.hpp), whatever
// technique lit the frame:
//   update():      VctPipeline::update (voxelize once, inject from the frame's
//                  lights, mips, 3D textures) on every frame, as if every light
//                  moved (the many-dynamic-lights case; static geometry stays
//                  voxelized; the hashed lists follow the lights incrementally,
//                  so unchanged lights cost them only a comparison); with
//                  `revoxelize` (moving geometry) every frame voxelizes first,
//                  and the rest follows it as on any frame;
//   addIndirect(): `vct-trace` (gl/shaders/vct_trace.comp: diffuse cones, the
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
// checkVctGiSettings(): UserError with one line naming the flag.
#include <memory>
#include <string>
#include <vector>

#include "gl/GiPass.hpp"
#include "host/vct/ConeTracing.hpp"
#include "host/vct/VctPipeline.hpp"

namespace ml::vct {

inline constexpr float kSpecularWeight = 0.04f;
inline constexpr float kSpecularApertureDeg = 10.0f;

struct VctGiSettings {
  VoxelGridSettings grid;   // --voxels, --levels, --anisotropic
  unsigned cones = 9;       // --cones
  float aperture_deg = 45;  // --cone-aperture
  float gi_scale = 0.5f;    // --gi-scale: trace resolution / frame resolution, (0, 1]
  bool specular = false;    // --specular
  std::string shadows = "none";  // --vct-shadows: none | voxel (visibility through level-0 opacity)
  bool revoxelize = false;       // --revoxelize: voxelize every frame (moving geometry), not only the first
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
  std::vector<float> ambientOcclusion() const;  // last frame, one float per pixel, 0 on the sky
  const VctGiSettings& settings() const { return s_; }
  const VctPipeline& pipeline() const { return pipeline_; }  // the voxel volume, for debug views

 private:
  void allocate(unsigned width, unsigned height);
  void freeImages();
  void trace(const GiFrameInputs& in);
  void upsample(const GiFrameInputs& in);

  VctGiSettings s_;
  VctPipeline pipeline_;
  std::vector<Cone> cones_;
  ShaderProgram trace_, upsample_;
  unsigned width_ = 0, height_ = 0, lo_w_ = 0, lo_h_ = 0;
  GLuint lo_irradiance_ = 0, lo_geometry_ = 0, lo_specular_ = 0, indirect_ = 0, ao_ = 0;
};

}  // namespace ml::vct
