#include "host/vct/VoxelView.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <string>

#include "gl/GlCheck.hpp"
#include "gl/Texture2d.hpp"
#include "host/shared/vct_bindings.h"
#include "host/util/Error.hpp"
#include "host/util/GiToneMap.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kGroup = 8;  // voxel_view.comp's local size per axis

// The shader indexes each buffer whole: one larger than the GL's shader
// storage block limit would read past it, so it is refused.
void checkBlockLimit(const SharedBuffer& buffer) {
  GLint64 size = 0, max_block = 0;
  glGetNamedBufferParameteri64v(buffer.gl(), GL_BUFFER_SIZE, &size);
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  glCheck("querying the voxel volume's size");
  if (max_block > 0 && size > max_block)
    throw UserError("--voxel-view: a voxel volume of " + std::to_string(size >> 20) +
                    " MiB exceeds this GL's shader storage block limit (" + std::to_string(max_block >> 20) +
                    " MiB): use fewer --voxels");
}

}  // namespace

VoxelViewKind parseVoxelView(const std::string& name) {
  if (name == "albedo") return VoxelViewKind::Albedo;
  if (name == "radiance") return VoxelViewKind::Radiance;
  if (name == "opacity") return VoxelViewKind::Opacity;
  throw UserError(std::string("--voxel-view: expected ") + kVoxelViewNames + ", got '" + name + "'");
}

const char* voxelViewName(VoxelViewKind kind) {
  switch (kind) {
    case VoxelViewKind::Albedo: return "albedo";
    case VoxelViewKind::Radiance: return "radiance";
    case VoxelViewKind::Opacity: return "opacity";
  }
  return "?";
}

void checkVoxelLevel(unsigned level, unsigned levels) {
  if (level >= levels)
    throw UserError("--voxel-level: expected 0.." + std::to_string(levels - 1) + " (below --levels " +
                    std::to_string(levels) + "), got " + std::to_string(level));
}

std::vector<float> voxelViewDisplay(const std::vector<float>& rgba, VoxelViewKind kind) {
  std::vector<float> px = kind == VoxelViewKind::Radiance ? giToneMapped(rgba) : rgba;
  for (std::size_t i = 3; i < px.size(); i += 4) px[i] = 1.0f;
  return px;
}

VoxelViewPass::VoxelViewPass() : program_({"vct/voxel_view.comp"}) {}

std::vector<float> VoxelViewPass::render(const VoxelVolume& volume, VoxelViewKind kind, unsigned level,
                                         const VoxelViewCamera& camera) {
  checkVoxelLevel(level, volume.params().levels);
  const glm::mat4 inv_vp = glm::inverse(camera.proj * camera.view);
  const glm::vec3 eye = glm::vec3(glm::inverse(camera.view)[3]);
  program_.use();
  program_.set("u_inv_view_proj", glm::value_ptr(inv_vp));
  program_.set3("u_eye", eye.x, eye.y, eye.z);
  program_.set("u_slice", 0u);
  return dispatch(volume, kind, level, camera.width, camera.height);
}

std::vector<float> VoxelViewPass::renderSlice(const VoxelVolume& volume, VoxelViewKind kind, unsigned level,
                                              const VoxelSlice& slice, unsigned width, unsigned height) {
  const gpu::VoxelGridParams& grid = volume.params();
  checkVoxelLevel(level, grid.levels);
  const bool aniso = volume.settings().anisotropic && level > 0;
  program_.use();
  program_.set("u_slice", slice.axis + 1);
  program_.set("u_plane", voxelSlicePlane(slice, grid.edge >> level));
  program_.set("u_aniso_first", aniso ? gpu::voxel_aniso_index(grid.edge, level, 0, 0) : ~0u);
  return dispatch(volume, kind, level, width, height);
}

std::vector<float> VoxelViewPass::dispatch(const VoxelVolume& volume, VoxelViewKind kind, unsigned level,
                                           unsigned w, unsigned h) {
  const gpu::VoxelGridParams& grid = volume.params();
  const SharedBuffer* aniso = volume.anisotropic();
  for (const SharedBuffer* b : {&volume.radiance(), &volume.accum(), aniso})
    if (b) checkBlockLimit(*b);
  const GLuint image = makeTexture2d(GL_RGBA32F, w, h);  // an image only: its filtering is never used
  // Poisoned: a pixel the shader skipped reads NaN, not whatever the storage held.
  const float nan[4] = {std::nanf(""), std::nanf(""), std::nanf(""), std::nanf("")};
  glClearTexImage(image, 0, GL_RGBA, GL_FLOAT, nan);
  glCheck("creating the voxel view image");
  const gpu::ml_float4& ovs = grid.origin_voxel_size;
  program_.set4("u_origin_voxel_size", ovs.x, ovs.y, ovs.z, ovs.w);
  program_.set("u_edge", grid.edge);
  program_.set("u_level", level);
  program_.set("u_offset", gpu::voxel_level_offset(grid.edge, level));
  program_.set("u_kind", static_cast<unsigned>(kind));
  program_.setU2("u_size", w, h);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXEL_VIEW_RADIANCE, volume.radiance().gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXEL_VIEW_ACCUM, volume.accum().gl());
  // Without an anisotropic volume the shader reads no aniso buffer; bind something valid.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_VOXEL_VIEW_ANISO, aniso ? aniso->gl() : volume.radiance().gl());
  glBindImageTexture(ML_IMAGE_VOXEL_VIEW_OUT, image, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glDispatchCompute((w + kGroup - 1) / kGroup, (h + kGroup - 1) / kGroup, 1);
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
  std::vector<float> px(std::size_t(w) * h * 4);
  glGetTextureImage(image, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
  for (GLuint b : {ML_BINDING_VOXEL_VIEW_RADIANCE, ML_BINDING_VOXEL_VIEW_ACCUM, ML_BINDING_VOXEL_VIEW_ANISO})
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
  glDeleteTextures(1, &image);
  glCheck("voxel view");
  return px;
}

}  // namespace ml::vct
