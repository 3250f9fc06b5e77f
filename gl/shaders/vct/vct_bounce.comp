// Pass vct-bounce (--gi-bounces 2): per level-0 voxel, the light its
// surface gathers through the volume's cones (vct_cones.glsl, the first
// bounce's textures) added to its injected radiance, as Crassin et al. do
// for a second bounce: radiance += albedo * irradiance / pi. The voxel's
// surface is its centre with its mean normal; a voxel whose normals cancel
// (a sheet seen from both sides) or an empty one keeps its radiance. Writes
// level 0 of the radiance buffer only; the mips and textures are redone
// after it (VctPipeline::refilter).
#include "vct/vct_cones.glsl"
#include "vct_bindings.h"
layout(local_size_x = 64) in;

struct VoxelAccum {
  uvec4 albedo_count;
  ivec4 normal_sum;
};
layout(std430, binding = ML_BINDING_BOUNCE_ACCUM) readonly buffer AccumBuffer { VoxelAccum accum[]; };
layout(std430, binding = ML_BINDING_BOUNCE_RADIANCE) buffer RadianceBuffer { vec4 radiance[]; };
uniform uint u_edge_log2;

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint edge = 1u << u_edge_log2;
  if (i >= edge * edge * edge) return;
  VoxelAccum a = accum[i];
  if (a.albedo_count.w == 0u) return;
  vec3 n = vec3(a.normal_sum.xyz);
  if (dot(n, n) == 0.0) return;
  uint mask = edge - 1u;
  uvec3 v = uvec3(i & mask, (i >> u_edge_log2) & mask, i >> (2u * u_edge_log2));
  vec3 P = u_grid_origin_size.xyz + (vec3(v) + 0.5) * u_grid_origin_size.w;
  vec3 albedo = vec3(a.albedo_count.xyz) / (float(a.albedo_count.w) * float(ML_VOXEL_ALBEDO_SCALE_GLSL));
  vec3 gathered = traceDiffuse(P, normalize(n)).rgb;
  radiance[i].rgb += albedo * gathered;
}
