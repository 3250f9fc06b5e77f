#pragma once
// The camera uniforms of gl/shaders/common/common.glsl (u_view, u_proj, the inverse
// view u_inv_view, u_viewport), set the one way the frame's programs and the GI
// passes that reconstruct positions from its depth both need.
#include <glm/glm.hpp>

#include "gl/ShaderProgram.hpp"

namespace ml {

void setViewUniforms(const ShaderProgram& p, const glm::mat4& view, const glm::mat4& proj, unsigned width,
                     unsigned height);

}  // namespace ml
