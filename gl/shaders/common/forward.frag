// Depth test before shading, also when the counting atomics (side effects)
// would otherwise make the driver shade hidden fragments of a pre-pass frame.
layout(early_fragment_tests) in;
#include "common/common.glsl"
#include "common/material.glsl"
#include "lookup.glsl"
#include "common/shading.glsl"
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
layout(location = 0) out vec4 o_color;
layout(location = 1) out uvec2 o_counts;
void main() {
  vec3 N = normalize(v_normal);
  if (!gl_FrontFacing) N = -N;  // two-sided, as thin walls are seen from both sides
  vec3 view_pos = (u_view * vec4(v_world, 1.0)).xyz;
  vec3 P_bound = v_world;
#ifdef COUNT_LIGHTS
  // The in-range count uses the point the lower bound sees: reconstructed
  // from this fragment's depth, which is what the depth buffer keeps (32F).
  P_bound = viewToWorld(windowToView(gl_FragCoord.xy, gl_FragCoord.z));
#endif
  uvec2 counts;
  vec3 c = shadePoint(v_world, N, view_pos, gl_FragCoord.xy, P_bound, baseColor(v_uv).rgb, counts);
  o_color = vec4(c, 1.0);
  o_counts = counts;
}
