// Tests only: traceDiffuse (vct_cones.glsl) at given points and normals.
#include "vct_bindings.h"
#include "vct/vct_cones.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = ML_BINDING_TEST_CONES_POINTS) readonly buffer Points { vec4 points[]; };  // xyz
layout(std430, binding = ML_BINDING_TEST_CONES_NORMALS) readonly buffer Normals { vec4 normals[]; };  // xyz, unit
// irradiance / pi, ambient occlusion
layout(std430, binding = ML_BINDING_TEST_CONES_RESULTS) writeonly buffer Results { vec4 results[]; };
uniform uint u_count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  results[i] = traceDiffuse(points[i].xyz, normals[i].xyz);
}
