#include "host/vct/VoxelTextures.hpp"

#include <cstddef>

#include "gl/GlCheck.hpp"

namespace ml {
namespace {

GLuint makeTexture(unsigned edge, unsigned levels, bool wrap) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &t);
  glTextureStorage3D(t, static_cast<GLsizei>(levels), GL_RGBA16F, static_cast<GLsizei>(edge),
                     static_cast<GLsizei>(edge), static_cast<GLsizei>(edge));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Clamped to the edge texel: a cone stops where it leaves the grid
  // (vct_cones.glsl), so only samples in a level's outer half-texel see the
  // wrap, and there a wall at the grid's edge must stay a wall. With a
  // transparent border they blended it with empty space at every coarse
  // level: cones ended short of opacity (a furnace with a one-voxel shell at
  // the edge lost 37-47%; the Cornell box's energy was 0.75-0.84 of the
  // reference's). A toroidal grid (a cascade level) repeats: its window
  // starts at voxel_shift() and wraps around (the cones read it only inside
  // the window, away from the seam where its far side meets its near one).
  for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(t, w, wrap ? GL_REPEAT : GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(levels) - 1);
  glCheck("creating a voxel texture");
  return t;
}

// Level `level` (edge `e`) of `texture` from the bound pixel unpack buffer,
// starting at its float4 `first`.
void uploadLevel(GLuint texture, unsigned level, unsigned e, std::size_t first) {
  const GLsizei n = static_cast<GLsizei>(e);
  glTextureSubImage3D(texture, static_cast<GLint>(level), 0, 0, 0, n, n, n, GL_RGBA, GL_FLOAT,
                      reinterpret_cast<const void*>(first * sizeof(gpu::ml_float4)));
}

}  // namespace

VoxelTextures::~VoxelTextures() {
  glDeleteTextures(1, &radiance_);
  glDeleteTextures(static_cast<GLsizei>(dirs_.size()), dirs_.data());
}

void VoxelTextures::allocate(const gpu::VoxelGridParams& grid, bool aniso) {
  const bool same = grid.edge == edge_ && grid.levels == levels_ && (grid.wrap != 0) == wrap_;
  if (!same) {
    glDeleteTextures(1, &radiance_);
    glDeleteTextures(static_cast<GLsizei>(dirs_.size()), dirs_.data());
    dirs_.fill(0);
    radiance_ = makeTexture(grid.edge, grid.levels, grid.wrap != 0);
    edge_ = grid.edge;
    levels_ = grid.levels;
    wrap_ = grid.wrap != 0;
  }
  if (aniso && dirs_[0] == 0)
    for (GLuint& d : dirs_) d = makeTexture(grid.edge, grid.levels, wrap_);
}

void VoxelTextures::unpack(const gpu::VoxelGridParams& grid, GLuint radiance, GLuint aniso, GlPassTimer* timer) {
  GlPassScope scope(timer, "vct-textures");
  allocate(grid, aniso != 0);
  GLint previous = 0;
  glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &previous);
  // The volumes are tightly packed float4s; reset whatever unpack state a caller left.
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
  glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
  glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
  glPixelStorei(GL_UNPACK_SKIP_IMAGES, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, radiance);
  for (unsigned l = 0; l < grid.levels; ++l)
    uploadLevel(radiance_, l, grid.edge >> l, gpu::voxel_level_offset(grid.edge, l));
  if (aniso) {
    const GLsizei n = static_cast<GLsizei>(grid.edge);
    for (GLuint d : dirs_) glCopyImageSubData(radiance_, GL_TEXTURE_3D, 0, 0, 0, 0, d, GL_TEXTURE_3D, 0, 0, 0, 0, n, n, n);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, aniso);
    for (unsigned l = 1; l < grid.levels; ++l)
      for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d)
        uploadLevel(dirs_[d], l, grid.edge >> l, gpu::voxel_aniso_index(grid.edge, l, d, 0));
  }
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(previous));
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glCheck("unpacking the voxel volume into 3D textures");
}

}  // namespace ml
