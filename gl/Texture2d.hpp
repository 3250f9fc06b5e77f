#pragma once
// One 2D texture of immutable storage, one level, nearest filtering: the
// shape of every render target and of the GI passes' screen-space images.
// Errors are left for the caller's glCheck, which names its operation.
#include <epoxy/gl.h>

namespace ml {

inline GLuint makeTexture2d(GLenum internal_format, unsigned width, unsigned height) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, 1, internal_format, static_cast<GLsizei>(width), static_cast<GLsizei>(height));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

}  // namespace ml
