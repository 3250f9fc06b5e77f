// Pass vct-upsample: the reduced-resolution trace to full resolution, guided
// by depth and normal (joint bilateral): each pixel blends its 4x4 nearest
// low-resolution samples with a tent two samples wide per axis times
// exp(-|dz| / (0.05 z)) times max(n . n', 0)^8, so light does not bleed
// across depth edges or creases; with no similar sample, the plain tent over
// the covered ones. The tent spans every 2x2 block of vct_trace.comp's
// interleaved cone turns with near-equal weights (the 2x2 bilinear taps
// before it gave one turn 9/16 and left a checker pattern).
// indirect = (albedo * irradiance/pi + specular weight * specular) * u_radiance_scale
// is written to u_indirect (alpha 1 where covered), its ambient occlusion to
// u_ao, and added to the shaded image u_color.
#include "common/common.glsl"
#include "common/octahedral.glsl"
#include "vct_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = ML_UNIT_VCT_GBUFFER_ALBEDO) uniform sampler2D u_gbuffer_albedo;
layout(binding = ML_UNIT_VCT_GBUFFER_NORMAL) uniform sampler2D u_gbuffer_normal;
layout(binding = ML_UNIT_VCT_GBUFFER_DEPTH) uniform sampler2D u_gbuffer_depth;
layout(binding = ML_UNIT_VCT_LO_IRRADIANCE) uniform sampler2D u_lo_irradiance;
layout(binding = ML_UNIT_VCT_LO_GEOMETRY) uniform sampler2D u_lo_geometry;
layout(binding = ML_UNIT_VCT_LO_SPECULAR) uniform sampler2D u_lo_specular;
layout(rgba32f, binding = ML_IMAGE_VCT_UPSAMPLE_COLOR) uniform image2D u_color;
layout(rgba32f, binding = ML_IMAGE_VCT_UPSAMPLE_INDIRECT) uniform writeonly image2D u_indirect;
layout(r32f, binding = ML_IMAGE_VCT_UPSAMPLE_AO) uniform writeonly image2D u_ao;
uniform uvec2 u_lo_size;
uniform float u_radiance_scale;
uniform float u_specular_weight;
const float kTentSamples = 2.0;  // the tent's half-width, in low-resolution samples

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(vec2(px), u_viewport))) return;
  float depth = texelFetch(u_gbuffer_depth, px, 0).r;
  if (is_sky_depth(depth)) {
    imageStore(u_indirect, px, vec4(0.0));
    imageStore(u_ao, px, vec4(0.0));
    return;
  }
  vec3 N = octDecode(texelFetch(u_gbuffer_normal, px, 0).xy);
  float z = -windowToView(vec2(px) + 0.5, depth).z;
  vec2 q = (vec2(px) + 0.5) * vec2(u_lo_size) / u_viewport - 0.5;
  ivec2 base = ivec2(floor(q));
  vec2 f = q - vec2(base);
  vec4 ir = vec4(0.0), ir_plain = vec4(0.0);
  vec3 spec = vec3(0.0), spec_plain = vec3(0.0);
  float w_sum = 0.0, plain_sum = 0.0;
  for (int j = -1; j < 3; ++j)
    for (int i = -1; i < 3; ++i) {
      ivec2 t = clamp(base + ivec2(i, j), ivec2(0), ivec2(u_lo_size) - 1);
      vec4 g = texelFetch(u_lo_geometry, t, 0);
      if (g.w <= 0.0) continue;  // the sample sees the sky
      vec2 tent = max(vec2(1.0) - abs(vec2(i, j) - f) / kTentSamples, vec2(0.0));
      float bw = max(tent.x * tent.y, 1e-3);
      float w = bw * exp(-abs(g.w - z) / (0.05 * z)) * pow(max(dot(g.xyz, N), 0.0), 8.0);
      vec4 s_ir = texelFetch(u_lo_irradiance, t, 0);
      vec3 s_spec = texelFetch(u_lo_specular, t, 0).rgb;
      ir += w * s_ir;
      spec += w * s_spec;
      w_sum += w;
      ir_plain += bw * s_ir;
      spec_plain += bw * s_spec;
      plain_sum += bw;
    }
  if (w_sum > 1e-6) {
    ir /= w_sum;
    spec /= w_sum;
  } else if (plain_sum > 0.0) {
    ir = ir_plain / plain_sum;
    spec = spec_plain / plain_sum;
  }
  vec3 albedo = texelFetch(u_gbuffer_albedo, px, 0).rgb;
  vec3 indirect = (albedo * ir.rgb + u_specular_weight * spec) * u_radiance_scale;
  imageStore(u_indirect, px, vec4(indirect, 1.0));
  imageStore(u_ao, px, vec4(ir.a));
  vec4 c = imageLoad(u_color, px);
  imageStore(u_color, px, vec4(c.rgb + indirect, c.a));
}
