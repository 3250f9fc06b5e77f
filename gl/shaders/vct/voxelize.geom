// Voxelization, stage 2 (002: dominant-axis projection). Each triangle is
// projected along the axis its face normal is largest in, onto a viewport of
// edge x edge pixels = voxels, so it covers as many pixels as possible.
// Conservative rasterisation by triangle dilation (Hasselgren et al., GPU Gems 2
// ch. 42): every edge line moves outward by the pixel's half-diagonal in the
// edge normal's metric, 0.5 * (|n.x| + |n.y|), and the new corners are where
// neighbouring moved lines meet. Then every pixel whose square touches the
// triangle has its centre inside the dilated one; the fragment shader drops
// the overshoot at sharp corners (2D bounds test, then the exact clip of the
// pixel's square against the triangle's own edges).
// All positions here are in voxel units of the grid ("grid space").
#include "vct_bindings.h"
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 vs_world[];
in vec3 vs_normal[];
in vec2 vs_uv[];
out vec3 gs_normal;
out vec2 gs_uv;
flat out uint gs_axis;           // 0: x dominant, 1: y, 2: z
flat out vec4 gs_bounds;         // projected triangle's 2D bounds, pixels (min.xy, max.xy)
flat out vec3 gs_depth_plane;    // depth(px) = .x + .y * px.x + .z * px.y
flat out vec3 gs_edges[3];       // undilated edges: inside where dot(.xy, px) <= .z

uniform vec4 u_origin_voxel_size;
uniform uint u_edge;            // level-0 voxels per axis = viewport edge, pixels
uniform bool u_dilate;           // false only in tests that show dilation matters
uniform int u_box_count;         // > 0: only these window boxes are written (voxelize.frag)
uniform ivec3 u_box_lo[ML_VOXEL_REGION_BOXES];
uniform ivec3 u_box_hi[ML_VOXEL_REGION_BOXES];

// Whether the triangle's bounds (grid space, one voxel wider for the
// dilation) reach a box of the region: a scrolled slab rasterises only the
// triangles that can write to it.
bool reachesRegion(vec3 lo, vec3 hi) {
  if (u_box_count == 0) return true;
  for (int b = 0; b < u_box_count; ++b)
    if (all(lessThan(lo - 1.0, vec3(u_box_hi[b]))) && all(greaterThan(hi + 1.0, vec3(u_box_lo[b])))) return true;
  return false;
}

// Rasterisers snap vertices to a sub-pixel grid (8 bits on llvmpipe and most
// GPUs: 1/256 pixel), which can move a dilated edge inward past the centre of a
// pixel the triangle enters by less than that (a rare crossed voxel left
// empty). The edges move out this much farther; the fragment shader's exact
// clip drops what the extra margin lets in.
const float kSnapMargin = 1.0 / 64.0;

// Grid space -> (projection plane x, y, depth) for the dominant axis.
vec3 swizzleFor(uint axis, vec3 g) {
  if (axis == 0u) return g.yzx;
  if (axis == 1u) return g.zxy;
  return g;
}

// Where the lines dot(n0, x) = c0 and dot(n1, x) = c1 meet.
vec2 meet(vec2 n0, float c0, vec2 n1, float c1) {
  float det = n0.x * n1.y - n0.y * n1.x;
  return vec2(c0 * n1.y - c1 * n0.y, n0.x * c1 - n1.x * c0) / det;
}

void main() {
  vec3 g[3];
  for (int i = 0; i < 3; ++i) g[i] = (vs_world[i] - u_origin_voxel_size.xyz) / u_origin_voxel_size.w;
  if (!reachesRegion(min(g[0], min(g[1], g[2])), max(g[0], max(g[1], g[2])))) return;
  vec3 face = cross(g[1] - g[0], g[2] - g[0]);
  vec3 a = abs(face);
  uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  vec3 n = swizzleFor(axis, face);
  if (n.z == 0.0) return;  // zero area: no surface to voxelize
  vec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = swizzleFor(axis, g[i]);
  // Plane through p[0]: n.x (x - x0) + n.y (y - y0) + n.z (d - d0) = 0.
  vec3 plane = vec3(p[0].z + (n.x * p[0].x + n.y * p[0].y) / n.z, -n.x / n.z, -n.y / n.z);
  vec2 lo = min(p[0].xy, min(p[1].xy, p[2].xy)), hi = max(p[0].xy, max(p[1].xy, p[2].xy));
  // Outward edge normals: n.z > 0 means counter-clockwise in the plane.
  float orient = n.z > 0.0 ? 1.0 : -1.0;
  vec2 en[3];
  float ec[3];
  vec3 edges[3];
  for (int i = 0; i < 3; ++i) {
    vec2 e = p[(i + 1) % 3].xy - p[i].xy;
    en[i] = orient * vec2(e.y, -e.x);
    edges[i] = vec3(en[i], dot(en[i], p[i].xy));
    ec[i] = edges[i].z + (u_dilate ? 0.5 * (abs(en[i].x) + abs(en[i].y)) + kSnapMargin * length(en[i]) : 0.0);
  }
  for (int i = 0; i < 3; ++i) {
    // Corner i lies on edges i-1 and i.
    vec2 q = meet(en[(i + 2) % 3], ec[(i + 2) % 3], en[i], ec[i]);
    gs_normal = vs_normal[i];
    gs_uv = vs_uv[i];
    gs_axis = axis;
    gs_bounds = vec4(lo, hi);
    gs_depth_plane = plane;
    gs_edges = edges;
    gl_Position = vec4(q / float(u_edge) * 2.0 - 1.0, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
