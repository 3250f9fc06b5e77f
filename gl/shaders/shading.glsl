// The main thesis's shading model, exactly: white Lambert, attenuation
// (1 - d/r) clamped to [0,1] then squared, cosine clamped, ambient 0.1:
//   colour = base * (0.1 + 0.9 * sum_i I_i * cos_i * att_i)
// `lightListFor` and `nextLight` come from the technique's lookup_*.glsl.
vec3 computeLight(PointLight light, vec3 P, vec3 N) {
  vec3 L = light.position_radius.xyz - P;
  float d = length(L);
  L /= max(d, 1e-20);
  float attenuation = clamp(1.0 - d / light.position_radius.w, 0.0, 1.0);
  attenuation *= attenuation;
  float cos_incidence = clamp(dot(N, L), 0.0, 1.0);
  return light.color.rgb * cos_incidence * attenuation;
}

// counts.x: lights evaluated; counts.y: of those, lights whose sphere contains P.
vec3 shadePoint(vec3 P, vec3 N, vec3 view_pos, vec2 frag_coord, vec3 base_color, out uvec2 counts) {
  LightList list = lightListFor(P, view_pos, frag_coord);
  vec3 acc = vec3(0.0);
  uint evaluated = 0u, in_range = 0u, light_index;
  while (nextLight(list, light_index)) {
    PointLight light = lights[light_index];
    acc += computeLight(light, P, N);
    ++evaluated;
#ifdef COUNT_LIGHTS
    vec3 dv = light.position_radius.xyz - P;
    if (dot(dv, dv) < light.position_radius.w * light.position_radius.w) in_range++;
#endif
  }
  counts = uvec2(evaluated, in_range);
#ifdef COUNT_LIGHTS
  uint before = atomicAdd(fragment_evaluations_lo, evaluated);
  if (before + evaluated < before) atomicAdd(fragment_evaluations_hi, 1u);
#endif
  return base_color * (vec3(0.1) + 0.9 * acc);
}
