// Shared declarations of every shading program. Buffer layouts mirror
// host/shared/gpu_types.h (std430). Binding points:
//   0 lights, 1 light index list, 2 per-technique ranges (light grid / cluster
//   list), 3..6 technique-specific, 7 statistics counters.
struct PointLight {
  vec4 position_radius;
  vec4 color;
};
layout(std430, binding = 0) readonly buffer LightBuffer { PointLight lights[]; };

uniform mat4 u_view;
uniform mat4 u_proj;
uniform mat4 u_inv_view;
uniform mat4 u_inv_proj;
uniform vec2 u_viewport;      // width, height in pixels
uniform uint u_light_count;

#ifdef COUNT_LIGHTS
// [0]: light evaluations summed over every shaded fragment (overdraw included).
layout(std430, binding = 7) buffer StatsBuffer { uint fragment_evaluations_lo; uint fragment_evaluations_hi; };
#endif
