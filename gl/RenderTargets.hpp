#pragma once
// Framebuffers of one resolution:
//  - output:  colour RGBA32F (linear), light counts RG32UI (evaluated, in range),
//             depth 32F (forward depth / pre-pass)
//  - gbuffer: albedo RGBA8, normal RG16 unorm (octahedral), depth 32F (deferred)
#include <epoxy/gl.h>

#include <cstdint>
#include <vector>

namespace ml {

class RenderTargets {
 public:
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

 private:
  unsigned width_, height_;
  GLuint output_fbo_ = 0, gbuffer_fbo_ = 0;
  GLuint color_ = 0, counts_ = 0, depth_ = 0;
  GLuint albedo_ = 0, normal_ = 0, gbuffer_depth_ = 0;
};

}  // namespace ml
