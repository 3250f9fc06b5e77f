#include "gl/VoxelTextures.hpp"

#include <string>

#include "gl/GlCheck.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

constexpr unsigned kGroup = 4;  // voxel_unpack.comp's local size per axis

GLuint makeTexture(unsigned edge, unsigned levels) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &t);
  glTextureStorage3D(t, static_cast<GLsizei>(levels), GL_RGBA16F, static_cast<GLsizei>(edge),
                     static_cast<GLsizei>(edge), static_cast<GLsizei>(edge));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Outside the grid is empty space: transparent black, not the edge voxels.
  for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(t, w, GL_CLAMP_TO_BORDER);
  const float border[4] = {0, 0, 0, 0};
  glTextureParameterfv(t, GL_TEXTURE_BORDER_COLOR, border);
  glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(levels) - 1);
  glCheck("creating a voxel texture");
  return t;
}

void checkBlockLimit(GLuint buffer) {
  GLint64 size = 0, max_block = 0;
  glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &size);
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  glCheck("querying the voxel volume's size");
  if (max_block > 0 && size > max_block)
    throw UserError("voxel volume of " + std::to_string(size >> 20) +
                    " MiB exceeds this GL's shader storage block limit (" + std::to_string(max_block >> 20) +
                    " MiB): use fewer --voxels");
}

}  // namespace

VoxelTextures::VoxelTextures() : program_({"voxel_unpack.comp"}) {}

VoxelTextures::~VoxelTextures() {
  glDeleteTextures(1, &radiance_);
  glDeleteTextures(static_cast<GLsizei>(dirs_.size()), dirs_.data());
}

void VoxelTextures::allocate(const gpu::VoxelGridParams& grid, bool aniso) {
  const bool same = grid.edge == edge_ && grid.levels == levels_;
  if (!same) {
    glDeleteTextures(1, &radiance_);
    glDeleteTextures(static_cast<GLsizei>(dirs_.size()), dirs_.data());
    dirs_.fill(0);
    radiance_ = makeTexture(grid.edge, grid.levels);
    edge_ = grid.edge;
    levels_ = grid.levels;
  }
  if (aniso && dirs_[0] == 0)
    for (GLuint& d : dirs_) d = makeTexture(grid.edge, grid.levels);
}

void VoxelTextures::unpackLevel(GLuint buffer, std::size_t offset, GLuint texture, unsigned edge, unsigned level) {
  glBindImageTexture(0, texture, static_cast<GLint>(level), GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
  program_.set("u_offset", static_cast<unsigned>(offset));
  program_.set("u_edge", edge);
  const GLuint groups = (edge + kGroup - 1) / kGroup;
  glDispatchCompute(groups, groups, groups);
}

void VoxelTextures::unpack(const gpu::VoxelGridParams& grid, GLuint radiance, GLuint aniso, GlPassTimer* timer) {
  checkBlockLimit(radiance);
  if (aniso) checkBlockLimit(aniso);
  GlPassScope scope(timer, "vct-textures");
  allocate(grid, aniso != 0);
  program_.use();
  for (unsigned l = 0; l < grid.levels; ++l) {
    const unsigned e = grid.edge >> l;
    const std::size_t offset = gpu::voxel_level_offset(grid.edge, l);
    unpackLevel(radiance, offset, radiance_, e, l);
    if (!aniso) continue;
    for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d) {
      if (l == 0)
        unpackLevel(radiance, 0, dirs_[d], e, 0);
      else
        unpackLevel(aniso, gpu::voxel_aniso_index(grid.edge, l, d, 0), dirs_[d], e, l);
    }
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA16F);
  glCheck("unpacking the voxel volume into 3D textures");
}

}  // namespace ml
