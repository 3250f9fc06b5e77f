// Voxelization, stage 1: world-space vertices straight through (the scene is
// flattened to world space on load); the geometry shader projects.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
out vec3 vs_world;
out vec3 vs_normal;
out vec2 vs_uv;
void main() {
  vs_world = a_position;
  vs_normal = a_normal;
  vs_uv = a_uv;
  gl_Position = vec4(0.0);
}
