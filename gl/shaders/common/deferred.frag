#include "common/common.glsl"
#include "lookup.glsl"
#include "common/shading.glsl"
#include "common/octahedral.glsl"
layout(binding = ML_UNIT_GBUFFER_ALBEDO) uniform sampler2D u_gbuffer_albedo;
layout(binding = ML_UNIT_GBUFFER_NORMAL) uniform sampler2D u_gbuffer_normal;
layout(binding = ML_UNIT_GBUFFER_DEPTH) uniform sampler2D u_gbuffer_depth;
layout(location = 0) out vec4 o_color;
layout(location = 1) out uvec2 o_counts;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(u_gbuffer_depth, px, 0).r;
  if (is_sky_depth(depth)) discard;  // background keeps the clear colour
  vec3 view_pos = windowToView(gl_FragCoord.xy, depth);
  vec3 P = viewToWorld(view_pos);
  vec3 N = octDecode(texelFetch(u_gbuffer_normal, px, 0).xy);
  uvec2 counts;
  vec3 c = shadePoint(P, N, view_pos, gl_FragCoord.xy, P, texelFetch(u_gbuffer_albedo, px, 0).rgb, counts);
  o_color = vec4(c, 1.0);
  o_counts = counts;
}
