#include "host/vct/VctGiPass.hpp"

#include <algorithm>
#include <cmath>

#include "gl/GlCheck.hpp"
#include "gl/Texture2d.hpp"
#include "gl/ViewUniforms.hpp"
#include "host/shared/shading_model.h"
#include "host/shared/vct_bindings.h"
#include "host/util/Error.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kGroup = 8;  // local size of vct_trace.comp and vct_upsample.comp per axis

VctPipelineOptions pipelineOptions(const VctGiSettings& s) {
  VctPipelineOptions o;
  o.grid = s.grid;
  o.brute_force = s.brute_inject;
  o.shadows = s.shadows == "voxel";
  o.revoxelize = s.revoxelize;
  o.cascades = s.cascades;
  o.fold = s.fold;
  return o;
}

ShaderDefines traceDefines(const VctGiSettings& s) {
  ShaderDefines d = coneTracingDefines(s.cascades);
  if (s.specular) d.push_back({"VCT_SPECULAR", "1"});
  return d;
}

GLuint groups(unsigned n) { return (n + kGroup - 1) / kGroup; }

}  // namespace

void checkVctGiSettings(const VctGiSettings& s) {
  checkVoxelGrid(s.grid);
  checkConeSettings(s.cones, s.aperture_deg, s.lod_bias);
  if (!(s.gi_scale > 0.0f && s.gi_scale <= 1.0f))
    throw UserError("--gi-scale: expected a fraction of the resolution in (0, 1], got " + std::to_string(s.gi_scale));
  if (s.shadows != "none" && s.shadows != "voxel")
    throw UserError("--vct-shadows: expected none|voxel, got '" + s.shadows + "'");
  if (s.bounces < 1 || s.bounces > kMaxVctBounces)
    throw UserError("--gi-bounces: --gi vct models 1.." + std::to_string(kMaxVctBounces) + ", got " +
                    std::to_string(s.bounces));
  checkCascades(s.cascades);
  if (s.cascades > 1 && s.bounces > 1)
    throw UserError("--gi-bounces " + std::to_string(s.bounces) + ": needs --vct-cascades 1 (the second bounce "
                    "gathers within one grid)");
  if (s.fold && s.cascades < 2)
    throw UserError("--vct-fold: needs --vct-cascades 2 or more (it folds a finer level into a coarser one)");
  if (s.cascades > 1 && s.shadows != "none")
    throw UserError("--vct-shadows " + s.shadows + ": needs --vct-cascades 1 (the shadow march reads one grid)");
}

VctGiPass::VctGiPass(ClRuntime& rt, const VctGiSettings& s, const Aabb& scene_bounds)
    : s_((checkVctGiSettings(s), s)),
      pipeline_(rt, pipelineOptions(s), scene_bounds),
      cones_(diffuseCones(s.cones)),
      cone_turn_(coneSetTurn(s.cones)),
      trace_({"vct/vct_trace.comp"}, traceDefines(s)),
      upsample_({"vct/vct_upsample.comp"}),
      bounce_(s.bounces > 1 ? std::make_unique<VoxelBouncePass>() : nullptr) {}

VctGiPass::~VctGiPass() { freeImages(); }

void VctGiPass::freeImages() {
  const GLuint all[] = {lo_irradiance_, lo_geometry_, lo_specular_, indirect_, ao_};
  glDeleteTextures(5, all);
  lo_irradiance_ = lo_geometry_ = lo_specular_ = indirect_ = ao_ = 0;
}

void VctGiPass::allocate(unsigned width, unsigned height) {
  if (width == width_ && height == height_) return;
  freeImages();
  width_ = width;
  height_ = height;
  lo_w_ = std::max(1u, static_cast<unsigned>(std::lround(double(width) * s_.gi_scale)));
  lo_h_ = std::max(1u, static_cast<unsigned>(std::lround(double(height) * s_.gi_scale)));
  lo_irradiance_ = makeTexture2d(GL_RGBA16F, lo_w_, lo_h_);
  lo_geometry_ = makeTexture2d(GL_RGBA32F, lo_w_, lo_h_);
  lo_specular_ = makeTexture2d(GL_RGBA16F, lo_w_, lo_h_);
  indirect_ = makeTexture2d(GL_RGBA32F, width, height);
  ao_ = makeTexture2d(GL_R32F, width, height);
  glCheck("creating the cone-tracing images");
}

void VctGiPass::update(const GiSceneInputs& in) {
  if (!volumeStale(in)) {
    ++reuses_;
    return;
  }
  const bool relight = in.lights_version == 0 || in.lights_version != volume_lights_;
  pipeline_.update(in.scene, in.lights, in.passes, {in.eye, relight});
  scrolls_ += pipeline_.lastUpdate().scrolled_levels;
  scrolled_voxels_ += pipeline_.lastUpdate().scrolled_voxels;
  // The second bounce: the voxels gather from the volume just built, then
  // the mips and textures take the sum (Crassin et al. 2011).
  if (bounce_) {
    GlPassTimer timer;
    bounce_->run(pipeline_.volume(), coneSetup(), &timer);
    timer.collect(in.passes);
    pipeline_.refilter(in.passes);
  }
  volume_lights_ = in.lights_version;
}

ConeTraceSetup VctGiPass::coneSetup() const {
  const bool aniso = pipeline_.volume().anisotropic() != nullptr;
  ConeTraceSetup setup{pipeline_.volume().params(), &pipeline_.textures(), aniso, cones_, s_.aperture_deg, s_.broken,
                       {}, s_.lod_bias};
  for (unsigned c = 0; c < pipeline_.cascades(); ++c)
    setup.levels.push_back({pipeline_.level(c).volume.params(), &pipeline_.level(c).textures});
  return setup;
}

// What the volume reads: the scene (voxelized on the first update, or on every
// one with revoxelize), the lights (by version: volume_lights_ starts at 0,
// which no light set has, so the first frame updates), the camera (cascades)
// and the settings (fixed).
bool VctGiPass::volumeStale(const GiSceneInputs& in) const {
  return s_.revoxelize || in.lights_version == 0 || in.lights_version != volume_lights_ ||
         (s_.cascades > 1 && pipeline_.moves(in.eye));
}

void VctGiPass::addIndirect(const GiFrameInputs& in) {
  allocate(in.width, in.height);
  trace(in);
  upsample(in);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glCheck("cone tracing");
}

void VctGiPass::trace(const GiFrameInputs& in) {
  GlPassScope scope(in.timer, "vct-trace");
  trace_.use();
  setViewUniforms(trace_, in.view, in.proj, in.width, in.height);
  bindConeTracing(trace_, coneSetup());
  trace_.setU2("u_lo_size", lo_w_, lo_h_);
  trace_.set("u_specular_tan", std::tan(kSpecularApertureDeg * 3.14159265f / 360.0f));
  trace_.set("u_cone_turn", cone_turn_);
  glBindTextureUnit(ML_UNIT_VCT_GBUFFER_NORMAL, in.normal);
  glBindTextureUnit(ML_UNIT_VCT_GBUFFER_DEPTH, in.depth);
  glBindImageTexture(ML_IMAGE_VCT_TRACE_IRRADIANCE, lo_irradiance_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  glBindImageTexture(ML_IMAGE_VCT_TRACE_GEOMETRY, lo_geometry_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(ML_IMAGE_VCT_TRACE_SPECULAR, lo_specular_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  glDispatchCompute(groups(lo_w_), groups(lo_h_), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glCheck("vct-trace");
}

void VctGiPass::upsample(const GiFrameInputs& in) {
  GlPassScope scope(in.timer, "vct-upsample");
  upsample_.use();
  setViewUniforms(upsample_, in.view, in.proj, in.width, in.height);
  upsample_.setU2("u_lo_size", lo_w_, lo_h_);
  upsample_.set("u_radiance_scale", 1.0f / ML_SHADE_DIRECT);
  upsample_.set("u_specular_weight", s_.specular ? kSpecularWeight : 0.0f);
  glBindTextureUnit(ML_UNIT_VCT_GBUFFER_ALBEDO, in.albedo);
  glBindTextureUnit(ML_UNIT_VCT_GBUFFER_NORMAL, in.normal);
  glBindTextureUnit(ML_UNIT_VCT_GBUFFER_DEPTH, in.depth);
  glBindTextureUnit(ML_UNIT_VCT_LO_IRRADIANCE, lo_irradiance_);
  glBindTextureUnit(ML_UNIT_VCT_LO_GEOMETRY, lo_geometry_);
  glBindTextureUnit(ML_UNIT_VCT_LO_SPECULAR, lo_specular_);
  glBindImageTexture(ML_IMAGE_VCT_UPSAMPLE_COLOR, in.color, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(ML_IMAGE_VCT_UPSAMPLE_INDIRECT, indirect_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(ML_IMAGE_VCT_UPSAMPLE_AO, ao_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(groups(width_), groups(height_), 1);
  glCheck("vct-upsample");
}

std::vector<float> VctGiPass::indirectRgba() const {
  std::vector<float> px(std::size_t(width_) * height_ * 4);
  if (indirect_)
    glGetTextureImage(indirect_, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  glCheck("reading the indirect image");
  return px;
}

std::vector<float> VctGiPass::ambientOcclusion() const {
  std::vector<float> px(std::size_t(width_) * height_);
  if (ao_) glGetTextureImage(ao_, 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  glCheck("reading the ambient occlusion image");
  return px;
}

std::size_t VctGiPass::memoryBytes() const {
  const std::size_t lo = std::size_t(lo_w_) * lo_h_, full = std::size_t(width_) * height_;
  std::size_t voxels = 0;
  for (unsigned c = 0; c < s_.cascades; ++c) {
    const VoxelGridSettings l = cascadeLevelSettings(s_.grid, s_.cascades, c);
    voxels += voxelsAllLevels(l.voxels, l.levels);
  }
  const std::size_t textures = voxels * 8 * (s_.grid.anisotropic ? 7 : 1);  // RGBA16F
  return pipeline_.bytes() + textures + lo * (8 + 16 + 8) + full * (16 + 4);
}

}  // namespace ml::vct
