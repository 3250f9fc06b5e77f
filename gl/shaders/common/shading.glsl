// The main thesis's shading model, exactly: white Lambert, attenuation
// (1 - d/r) clamped to [0,1] then squared, cosine clamped, ambient 0.1:
//   colour = base * (0.1 + 0.9 * sum_i I_i * cos_i * att_i)
// `LightList`, `lightListFor`, `listEnded` and `nextLight` come from the
// technique's lookup_*.glsl (contract: host/assign/LightAssigner.hpp).
vec3 computeLight(PointLight light, vec3 P, vec3 N) {
  vec3 L = light.position_radius.xyz - P;
  float d = length(L);
  L /= max(d, 1e-20);
  float attenuation = clamp(1.0 - d / light.position_radius.w, 0.0, 1.0);
  attenuation *= attenuation;
  float cos_incidence = clamp(dot(N, L), 0.0, 1.0);
  return light.color.rgb * cos_incidence * attenuation;
}

struct Shading {
  vec3 acc;
  uint evaluated;
  uint in_range;  // COUNT_LIGHTS: evaluated lights whose sphere contains P_bound
};

// One list entry: no loop inside (see LIGHT_BATCH below).
void shadeEntry(inout LightList list, vec3 P, vec3 N, vec3 P_bound, inout Shading s) {
  uint light_index;
  if (!nextLight(list, light_index)) return;
  PointLight light = lights[light_index];
  s.acc += computeLight(light, P, N);
  ++s.evaluated;
#ifdef COUNT_LIGHTS
  // The exact lower bound's predicate, operation for operation
  // (kernels/assign/exact_lower_bound.cl), so both count the same lights.
  precise vec3 dv = light.position_radius.xyz - P_bound;
  precise float d2 = dv.x * dv.x + dv.y * dv.y + dv.z * dv.z;
  precise float r2 = light.position_radius.w * light.position_radius.w;
  if (d2 < r2) s.in_range++;
#endif
}

// llvmpipe ends a shader invocation's loops after 65,535 iterations in total
// (one counter shared by every loop: LP_MAX_TGSI_LOOP_ITERATIONS), which
// silently dropped every light past the 65,535th. The list loop therefore
// visits 32 entries per iteration, unrolled here by hand (NIR does not unroll
// a loop with breaks): a pixel may have 65,535 x 32 (about 2.1M) list entries
// there; `missed_lights` in the frame's counts would show anything beyond.
#define SHADE_ENTRY shadeEntry(list, P, N, P_bound, s);
#define SHADE_ENTRY_4 SHADE_ENTRY SHADE_ENTRY SHADE_ENTRY SHADE_ENTRY
#define SHADE_ENTRY_32 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4 SHADE_ENTRY_4

// counts.x: lights evaluated; counts.y: of those, lights whose sphere contains
// P_bound (the surface point as the lower bound reconstructs it from depth).
vec3 shadePoint(vec3 P, vec3 N, vec3 view_pos, vec2 frag_coord, vec3 P_bound, vec3 base_color, out uvec2 counts) {
  LightList list = lightListFor(P, view_pos, frag_coord);
  Shading s = Shading(vec3(0.0), 0u, 0u);
  while (!listEnded(list)) {
    SHADE_ENTRY_32
  }
  counts = uvec2(s.evaluated, s.in_range);
#ifdef COUNT_LIGHTS
  uint before = atomicAdd(fragment_evaluations_lo, s.evaluated);
  if (before + s.evaluated < before) atomicAdd(fragment_evaluations_hi, 1u);
#endif
  return base_color * (vec3(0.1) + 0.9 * s.acc);
}
