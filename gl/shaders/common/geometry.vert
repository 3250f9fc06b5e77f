// World-space geometry (the scene is flattened to world space on load).
#include "common/common.glsl"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
// Same position math in the depth pre-pass and the shading pass, so EQUAL depth tests hold.
invariant gl_Position;
void main() {
  v_world = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  gl_Position = u_proj * (u_view * vec4(a_position, 1.0));
}
