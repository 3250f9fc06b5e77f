// Pass vct-trace: per pixel of the reduced-resolution image, the G-buffer
// texel under its centre, its diffuse cones (vct_cones.glsl) and, with
// VCT_SPECULAR, one specular cone along the mirror direction.
// Interleaved cones (Keller and Heidrich 2001): each 2x2 block of pixels
// turns the cone set about the normal by 0, 2, 3 and 1 quarters of its
// rotational period (u_cone_turn, a quarter of it: host/vct/ConeTracing.hpp
// coneSetTurn), so the four neighbours' cones march through different
// voxels and vct_upsample.comp, whose taps span the block, averages them;
// one fixed set left low-frequency patches where its wide cones read coarse
// levels (Cornell box, 9 cones: 0.156 / 0.147 / 0.138 -> 0.142 / 0.136 /
// 0.126 at 32^3 / 64^3 / 128^3, docs/vct.md).
#include "common/common.glsl"
#include "common/octahedral.glsl"
#include "vct/vct_cones.glsl"
#include "vct_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = ML_UNIT_VCT_GBUFFER_NORMAL) uniform sampler2D u_gbuffer_normal;
layout(binding = ML_UNIT_VCT_GBUFFER_DEPTH) uniform sampler2D u_gbuffer_depth;
// irradiance / pi, ambient occlusion
layout(rgba16f, binding = ML_IMAGE_VCT_TRACE_IRRADIANCE) uniform writeonly image2D u_irradiance;
// normal, view distance (0: sky)
layout(rgba32f, binding = ML_IMAGE_VCT_TRACE_GEOMETRY) uniform writeonly image2D u_geometry;
// the specular cone's radiance
layout(rgba16f, binding = ML_IMAGE_VCT_TRACE_SPECULAR) uniform writeonly image2D u_specular;
uniform uvec2 u_lo_size;
uniform float u_specular_tan;  // tan(aperture / 2) of the specular cone
uniform float u_cone_turn;     // a quarter of the diffuse cone set's rotational period, radians
const int kTurnOrder[4] = int[4](0, 2, 3, 1);  // quarters by pixel: (x & 1) + 2 (y & 1)

void main() {
  ivec2 q = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(q), u_lo_size))) return;
  ivec2 px = min(ivec2((vec2(q) + 0.5) * u_viewport / vec2(u_lo_size)), ivec2(u_viewport) - 1);
  float depth = texelFetch(u_gbuffer_depth, px, 0).r;
  if (is_sky_depth(depth)) {
    imageStore(u_irradiance, q, vec4(0.0));
    imageStore(u_geometry, q, vec4(0.0));
    imageStore(u_specular, q, vec4(0.0));
    return;
  }
  vec3 view_pos = windowToView(vec2(px) + 0.5, depth);
  vec3 P = viewToWorld(view_pos);
  vec3 N = octDecode(texelFetch(u_gbuffer_normal, px, 0).xy);
  float turn = u_cone_turn * float(kTurnOrder[(q.x & 1) + 2 * (q.y & 1)]);
  imageStore(u_irradiance, q, traceDiffuse(P, N, turn));
  imageStore(u_geometry, q, vec4(N, -view_pos.z));
  vec4 spec = vec4(0.0);
#ifdef VCT_SPECULAR
  vec3 R = reflect(normalize(P - u_inv_view[3].xyz), N);
  spec = traceCone(P, N, R, u_specular_tan);
#endif
  imageStore(u_specular, q, vec4(spec.rgb, 1.0));
}
