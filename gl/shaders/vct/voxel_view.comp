// The voxel view (host/vct/VoxelView.hpp): per pixel, the camera ray marched
// through one level of the voxel grid (3D DDA) to the first voxel with
// opacity > 0 (cubes), or the voxel of one plane of the level under the pixel
// (slice mode). host/vct/VoxelViewTwin.cpp repeats these operations in this
// order (keep them in step).
#include "vct_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

struct VoxelAccum {
  uvec4 albedo_count;
  ivec4 normal_sum;
};
layout(std430, binding = ML_BINDING_VOXEL_VIEW_RADIANCE) readonly buffer Radiance { vec4 radiance[]; };
layout(std430, binding = ML_BINDING_VOXEL_VIEW_ACCUM) readonly buffer Accum { VoxelAccum accum[]; };
layout(std430, binding = ML_BINDING_VOXEL_VIEW_ANISO) readonly buffer Aniso { vec4 aniso[]; };
layout(rgba32f, binding = ML_IMAGE_VOXEL_VIEW_OUT) uniform writeonly image2D u_out;

uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;
uniform vec4 u_origin_voxel_size;  // level 0's corner and voxel edge
uniform uint u_edge;               // level 0's voxels per axis
uniform uint u_level;
uniform uint u_offset;             // the level's first voxel in `radiance`
uniform uint u_kind;               // 0 albedo, 1 radiance, 2 opacity
uniform uvec2 u_size;
uniform uint u_slice;        // 0: cubes; 1, 2, 3: the plane normal to x, y, z
uniform uint u_plane;        // slice: the plane's voxel layer
uniform uint u_aniso_first;  // slice, anisotropic level >= 1: the level's first float4 in `aniso`; else ~0u

// Mean albedo of the level-0 voxels under level-`u_level` voxel `cell`.
vec3 meanAlbedo(ivec3 cell) {
  const int n = 1 << u_level;
  uvec4 sum = uvec4(0);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const ivec3 p = cell * n + ivec3(x, y, z);
        sum += accum[uint(p.x) + u_edge * (uint(p.y) + u_edge * uint(p.z))].albedo_count;
      }
  if (sum.w == 0u) return vec3(0.0);
  return vec3(sum.xyz) / (255.0 * float(sum.w));
}

vec4 shade(ivec3 cell, vec4 v) {
  if (u_kind == 0u) return vec4(meanAlbedo(cell), 1.0);
  if (u_kind == 1u) return vec4(v.rgb / v.a, 1.0);
  return vec4(vec3(v.a), 1.0);
}

vec4 march(vec3 eye, vec3 dir) {
  const uint e = u_edge >> u_level;
  const float size = u_origin_voxel_size.w * float(1u << u_level);
  const vec3 o = (eye - u_origin_voxel_size.xyz) / size;
  vec3 d = dir / size;
  d = mix(d, vec3(1e-20), lessThan(abs(d), vec3(1e-20)));  // no division by zero
  const vec3 inv = vec3(1.0) / d;
  const vec3 t0 = (vec3(0.0) - o) * inv, t1 = (vec3(float(e)) - o) * inv;
  const vec3 tlo = min(t0, t1), thi = max(t0, t1);
  const float tenter = max(max(tlo.x, tlo.y), tlo.z);
  const float tmin = max(tenter, 0.0);
  const float tmax = min(min(thi.x, thi.y), thi.z);
  if (tmax < tmin) return vec4(0.0);
  const ivec3 last = ivec3(int(e) - 1);
  ivec3 cell = clamp(ivec3(floor(o + d * tmin)), ivec3(0), last);
  const ivec3 stp = ivec3(greaterThan(d, vec3(0.0))) * 2 - 1;
  vec3 next = (vec3(cell + max(stp, ivec3(0))) - o) * inv;
  const vec3 delta = abs(inv);
  const uint first = tenter < 0.0 ? 1u : 0u;  // the eye's own voxel is not shown
  for (uint i = 0u; i < 3u * e + 1u; ++i) {
    const vec4 v = radiance[u_offset + uint(cell.x) + e * (uint(cell.y) + e * uint(cell.z))];
    if (i >= first && v.a > 0.0) return shade(cell, v);
    if (next.x < next.y && next.x < next.z) {
      cell.x += stp.x;
      next.x += delta.x;
    } else if (next.y < next.z) {
      cell.y += stp.y;
      next.y += delta.y;
    } else {
      cell.z += stp.z;
      next.z += delta.z;
    }
    if (any(lessThan(cell, ivec3(0))) || any(greaterThan(cell, last))) break;
  }
  return vec4(0.0);
}

// Slices of anisotropic levels >= 1 show the mean of the 6 directions' values.
vec4 sliceValue(ivec3 cell) {
  const uint e = u_edge >> u_level;
  const uint i = uint(cell.x) + e * (uint(cell.y) + e * uint(cell.z));
  if (u_aniso_first == ~0u) return radiance[u_offset + i];
  vec4 sum = vec4(0.0);
  for (uint d = 0u; d < 6u; ++d) sum += aniso[u_aniso_first + d * e * e * e + i];
  return sum / 6.0;
}

// The plane fills the centred square of side min(width, height); pixel ->
// voxel in integers, so that the twin picks the same voxel.
vec4 slice(uvec2 px) {
  const uint e = u_edge >> u_level;
  const uint side = min(u_size.x, u_size.y);
  const uvec2 lo = (u_size - uvec2(side)) / 2u;
  if (any(lessThan(px, lo)) || any(greaterThanEqual(px, lo + uvec2(side)))) return vec4(0.0);
  const uvec2 uv = (px - lo) * e / side;
  const int k = int(u_plane), u = int(uv.x), v = int(uv.y);
  const ivec3 cell = u_slice == 1u ? ivec3(k, v, u) : (u_slice == 2u ? ivec3(u, k, v) : ivec3(u, v, k));
  const vec4 value = sliceValue(cell);
  return value.a > 0.0 ? shade(cell, value) : vec4(0.0);
}

void main() {
  const uvec2 px = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(px, u_size))) return;
  if (u_slice != 0u) {
    imageStore(u_out, ivec2(px), slice(px));
    return;
  }
  const vec2 ndc = (vec2(px) + 0.5) / vec2(u_size) * 2.0 - 1.0;
  const vec4 p = u_inv_view_proj * vec4(ndc, 0.5, 1.0);
  imageStore(u_out, ivec2(px), march(u_eye, p.xyz / p.w - u_eye));
}
