// Voxelization, stage 3: one fragment = one pixel column along the dominant
// axis. The pixel's square is clipped to the triangle (Sutherland-Hodgman
// against its three edges); the plane's depths over that polygon are the
// depths at which the triangle itself crosses the column, so every voxel of
// the column in that range is crossed and receives the fragment (up to three:
// the slope is at most 1 per axis after dominant-axis projection). Sums are
// integers (host/shared/voxel_types.h: order-independent atomicAdd).
#include "common/material.glsl"
#include "vct_bindings.h"
in vec3 gs_normal;
in vec2 gs_uv;
flat in uint gs_axis;
flat in vec4 gs_bounds;
flat in vec3 gs_depth_plane;
flat in vec3 gs_edges[3];

struct VoxelAccum {
  uvec4 albedo_count;
  ivec4 normal_sum;
};
layout(std430, binding = ML_BINDING_VOXELIZE_ACCUM) buffer VoxelAccumBuffer { VoxelAccum voxels[]; };
uniform uint u_edge;
// Toroidal grids (voxel_types.h, wrap): window voxel v is stored at
// (v + u_shift) mod edge (0 otherwise). With u_box_count > 0 only the voxels
// in these window boxes (hi exclusive) are written: a scrolled cascade
// level's new slabs (host/vct/VoxelRegion.hpp).
uniform uvec3 u_shift;
uniform int u_box_count;
uniform ivec3 u_box_lo[ML_VOXEL_REGION_BOXES];
uniform ivec3 u_box_hi[ML_VOXEL_REGION_BOXES];

bool inRegion(ivec3 v) {
  if (u_box_count == 0) return true;
  for (int b = 0; b < u_box_count; ++b)
    if (all(greaterThanEqual(v, u_box_lo[b])) && all(lessThan(v, u_box_hi[b]))) return true;
  return false;
}

// (plane x, plane y, depth) voxel -> grid (x, y, z): the inverse of swizzleFor.
uvec3 unswizzle(uint axis, uvec3 v) {
  if (axis == 0u) return v.zxy;
  if (axis == 1u) return v.yzx;
  return v;
}

// The plane's depth range over the part of the pixel's square inside the
// triangle; false when nothing is left (the square only touched the dilation).
bool depthRangeInTriangle(vec2 c, out float dmin, out float dmax) {
  vec2 poly[8];
  vec2 clipped[8];
  int n = 4;
  poly[0] = c + vec2(-0.5, -0.5);
  poly[1] = c + vec2(0.5, -0.5);
  poly[2] = c + vec2(0.5, 0.5);
  poly[3] = c + vec2(-0.5, 0.5);
  for (int e = 0; e < 3; ++e) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      vec2 a = poly[i], b = poly[(i + 1) % n];
      float fa = dot(gs_edges[e].xy, a) - gs_edges[e].z, fb = dot(gs_edges[e].xy, b) - gs_edges[e].z;
      if (fa <= 0.0) clipped[m++] = a;
      if ((fa <= 0.0) != (fb <= 0.0)) clipped[m++] = a + (b - a) * (fa / (fa - fb));
    }
    n = m;
    for (int i = 0; i < n; ++i) poly[i] = clipped[i];
  }
  dmin = 1e30;
  dmax = -1e30;
  for (int i = 0; i < n; ++i) {
    float d = gs_depth_plane.x + gs_depth_plane.y * poly[i].x + gs_depth_plane.z * poly[i].y;
    dmin = min(dmin, d);
    dmax = max(dmax, d);
  }
  return n > 0;
}

void main() {
  vec2 c = gl_FragCoord.xy;
  // Cheap first: the pixel's square misses the triangle's 2D bounds.
  if (any(lessThan(c, gs_bounds.xy - 0.5)) || any(greaterThan(c, gs_bounds.zw + 0.5))) discard;
  float d0, d1;
  if (!depthRangeInTriangle(c, d0, d1)) discard;
  int z0 = max(int(floor(d0)), 0), z1 = min(int(floor(d1)), int(u_edge) - 1);
  vec4 albedo = clamp(baseColor(gs_uv), 0.0, 1.0);
  uvec3 a = uvec3(round(albedo.rgb * 255.0));
  vec3 nrm = gs_normal;
  float len = length(nrm);
  ivec3 n = len > 0.0 ? ivec3(round(nrm / len * 1024.0)) : ivec3(0);
  uvec2 column = uvec2(c);
  for (int z = z0; z <= z1; ++z) {
    uvec3 v = unswizzle(gs_axis, uvec3(column, uint(z)));
    if (!inRegion(ivec3(v))) continue;
    v = (v + u_shift) & uvec3(u_edge - 1u);
    uint i = v.x + u_edge * (v.y + u_edge * v.z);
    atomicAdd(voxels[i].albedo_count.x, a.x);
    atomicAdd(voxels[i].albedo_count.y, a.y);
    atomicAdd(voxels[i].albedo_count.z, a.z);
    atomicAdd(voxels[i].albedo_count.w, 1u);
    atomicAdd(voxels[i].normal_sum.x, n.x);
    atomicAdd(voxels[i].normal_sum.y, n.y);
    atomicAdd(voxels[i].normal_sum.z, n.z);
  }
}
