#include "gl/ViewUniforms.hpp"

#include <glm/gtc/type_ptr.hpp>

namespace ml {

void setViewUniforms(const ShaderProgram& p, const glm::mat4& view, const glm::mat4& proj, unsigned width,
                     unsigned height) {
  const glm::mat4 inv_view = glm::inverse(view);
  p.set("u_view", glm::value_ptr(view));
  p.set("u_proj", glm::value_ptr(proj));
  p.set("u_inv_view", glm::value_ptr(inv_view));
  p.set2("u_viewport", static_cast<float>(width), static_cast<float>(height));
}

}  // namespace ml
