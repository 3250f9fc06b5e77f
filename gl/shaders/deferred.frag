#include "common.glsl"
#include "depth_convention.h"
#include "lookup.glsl"
#include "shading.glsl"
#include "octahedral.glsl"
layout(binding = 1) uniform sampler2D u_gbuffer_albedo;
layout(binding = 2) uniform sampler2D u_gbuffer_normal;
layout(binding = 3) uniform sampler2D u_gbuffer_depth;
layout(location = 0) out vec4 o_color;
layout(location = 1) out uvec2 o_counts;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(u_gbuffer_depth, px, 0).r;
  if (is_sky_depth(depth)) discard;  // background keeps the clear colour
  // View position from the distance and the pixel's ray, as the kernels
  // reconstruct it (kernels/cluster_assign.cl): no inverse projection whose
  // float rounding would grow with far / near.
  float z = depth_to_distance(depth, u_proj[2][2], u_proj[3][2]);
  vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
  vec3 view_pos = z * vec3((ndc + vec2(u_proj[2][0], u_proj[2][1])) / vec2(u_proj[0][0], u_proj[1][1]), -1.0);
  vec3 P = (u_inv_view * vec4(view_pos, 1.0)).xyz;
  vec3 N = octDecode(texelFetch(u_gbuffer_normal, px, 0).xy);
  uvec2 counts;
  vec3 c = shadePoint(P, N, view_pos, gl_FragCoord.xy, texelFetch(u_gbuffer_albedo, px, 0).rgb, counts);
  o_color = vec4(c, 1.0);
  o_counts = counts;
}
