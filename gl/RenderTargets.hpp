#pragma once
// Framebuffers of one resolution:
//  - output:  colour RGBA32F (linear), light counts RG32UI (evaluated, in range),
//             depth 32F + stencil 8 (forward depth / pre-pass; the stencil lets
//             the shading pass keep the first of equal-depth fragments)
//  - gbuffer: albedo RGBA8, normal RG16 unorm (octahedral), depth 32F (deferred)
// Depth is reversed-Z float (host/shared/depth_convention.h).
// The size is checked against the GL limits, what the driver will allocate and
// a memory budget before anything is created: UserError naming --size.
#include <epoxy/gl.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ml {

class RenderTargets {
 public:
  // Throws UserError (checkSize) if the targets cannot be made at this size.
  RenderTargets(unsigned width, unsigned height);
  ~RenderTargets();
  RenderTargets(const RenderTargets&) = delete;
  RenderTargets& operator=(const RenderTargets&) = delete;

  unsigned width() const { return width_; }
  unsigned height() const { return height_; }
  GLuint outputFbo() const { return output_fbo_; }
  GLuint gbufferFbo() const { return gbuffer_fbo_; }
  GLuint albedoTexture() const { return albedo_; }
  GLuint normalTexture() const { return normal_; }
  GLuint gbufferDepthTexture() const { return gbuffer_depth_; }
  GLuint outputColorTexture() const { return color_; }

  // Read-backs; rows bottom-up (GL order).
  std::vector<float> readColor() const;                 // RGBA
  std::vector<std::uint32_t> readCounts() const;        // (evaluated, in range) pairs
  std::vector<float> readDepth(bool deferred) const;    // window-space depth

  // Bytes per pixel of all targets plus the depth copy the kernels read.
  static constexpr std::size_t kBytesPerPixel = 16 + 8 + 8 + 4 + 4 + 4 + 4;
  // Throws UserError naming --size and the largest size of the same aspect
  // ratio that passes, when width x height exceeds a GL size limit
  // (GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE, GL_MAX_VIEWPORT_DIMS,
  // GL_MAX_FRAMEBUFFER_WIDTH/HEIGHT), a proxy texture of some target's format
  // is refused (Mesa 22.3.6 llvmpipe: about 1.5 GiB per texture), or the targets
  // need more than memoryBudget(). Allocates nothing. Needs a current context.
  static void checkSize(unsigned width, unsigned height);
  // Half the physical memory (software GL keeps textures there), and at most
  // the dedicated video memory where GL_NVX_gpu_memory_info reports it.
  static std::size_t memoryBudget();

 private:
  unsigned width_, height_;
  GLuint output_fbo_ = 0, gbuffer_fbo_ = 0;
  GLuint color_ = 0, counts_ = 0, depth_ = 0;
  GLuint albedo_ = 0, normal_ = 0, gbuffer_depth_ = 0;
};

}  // namespace ml
