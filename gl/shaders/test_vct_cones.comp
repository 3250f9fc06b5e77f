// Tests only: traceDiffuse (vct_cones.glsl) at given points and normals.
#include "vct_cones.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };    // xyz
layout(std430, binding = 2) readonly buffer Normals { vec4 normals[]; };  // xyz, unit
layout(std430, binding = 3) writeonly buffer Results { vec4 results[]; }; // irradiance / pi, ambient occlusion
uniform uint u_count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  results[i] = traceDiffuse(points[i].xyz, normals[i].xyz);
}
