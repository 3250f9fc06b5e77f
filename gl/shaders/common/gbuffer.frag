#include "common/common.glsl"
#include "common/material.glsl"
#include "common/octahedral.glsl"
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
layout(location = 0) out vec4 o_albedo;
layout(location = 1) out vec2 o_normal;  // octahedral, RG16 unorm
void main() {
  vec3 N = normalize(v_normal);
  if (!gl_FrontFacing) N = -N;
  o_albedo = vec4(baseColor(v_uv).rgb, 1.0);
  o_normal = octEncode(N);
}
