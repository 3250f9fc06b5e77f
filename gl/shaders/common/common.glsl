// Shared declarations of every shading program. Buffer layouts mirror
// host/shared/gpu_types.h (std430); binding points come from
// host/shared/shading_bindings.h (0 lights, 7 statistics counters, 1..6 the
// technique's).
#include "shading_bindings.h"
struct PointLight {
  vec4 position_radius;
  vec4 color;
};
layout(std430, binding = ML_BINDING_LIGHTS) readonly buffer LightBuffer { PointLight lights[]; };

uniform mat4 u_view;
uniform mat4 u_proj;
uniform mat4 u_inv_view;
uniform vec2 u_viewport;      // width, height in pixels
uniform uint u_light_count;

#ifdef COUNT_LIGHTS
// [0]: light evaluations summed over every shaded fragment (overdraw included).
layout(std430, binding = ML_BINDING_STATS) buffer StatsBuffer { uint fragment_evaluations_lo; uint fragment_evaluations_hi; };
#endif

#include "depth_convention.h"
// Window space (pixel centre, reversed-Z depth) -> view and world space: the
// one place shaders undo the projection. The view position comes from the
// distance (depth_convention.h) along the pixel's ray, as the kernels
// reconstruct it: no inverse projection whose rounding grows with far / near.
// The exact lower bound's kernel (kernels/assign/exact_lower_bound.cl,
// window_to_world) repeats these operations in this order, hence `precise`
// (no fused multiply-adds).
vec3 windowToView(vec2 frag_coord, float depth) {
  precise float z = depth_to_distance(depth, u_proj[2][2], u_proj[3][2]);
  precise vec2 ndc = frag_coord / u_viewport * 2.0 - 1.0;
  precise vec2 xy = (ndc + vec2(u_proj[2][0], u_proj[2][1])) / vec2(u_proj[0][0], u_proj[1][1]);
  precise vec3 view_pos = vec3(z * xy, -z);
  return view_pos;
}
vec3 viewToWorld(vec3 view_pos) {
  precise vec4 w = u_inv_view * vec4(view_pos, 1.0);
  return w.xyz;
}
