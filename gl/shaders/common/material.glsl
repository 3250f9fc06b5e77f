uniform vec4 u_base_color;
uniform bool u_has_texture;
#include "shading_bindings.h"
layout(binding = ML_UNIT_BASE_TEXTURE) uniform sampler2D u_base_texture;
vec4 baseColor(vec2 uv) {
  vec4 c = u_base_color;
  if (u_has_texture) c *= texture(u_base_texture, uv);
  return c;
}
