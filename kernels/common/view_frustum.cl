/* View-space geometry of the culling kernels (tiled/, clustered/), defined
 * once: the camera matrices' products, a screen tile's NDC edges, and the
 * view-space box of a tile's frustum between two distances.
 *
 * Contract: every function is the exact float sequence of its C++ mirror
 * (host/tiled/TileGeometry.cpp, host/clustered/ClusterGeometry.cpp), so the
 * device and the twins reach the same decisions bit for bit; hence no
 * contraction into fused multiply-adds. The pragma below holds for the rest
 * of the includer too, so only kernels that turn contraction off themselves
 * (all that mirror C++) include this. The matrices are glm's column-major 4x4 in private memory (a CameraParams
 * passed by value), element (row r, col c) at m[c * 4 + r]. Distances are
 * positive (view-space -z). */
#ifndef ML_COMMON_VIEW_FRUSTUM_CL
#define ML_COMMON_VIEW_FRUSTUM_CL

#pragma OPENCL FP_CONTRACT OFF

/* Relative widening of culling depth ranges (tile and cluster boxes, light
 * depth spans): the kernels and the shaders reconstruct depth along
 * different float paths, so a shaded point must not fall between the two. */
#define DEPTH_EPS 1e-4f

inline float4 mat_mul(const float* m, float4 v) {
  return (float4)(m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12] * v.w,
                  m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13] * v.w,
                  m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14] * v.w,
                  m[3] * v.x + m[7] * v.y + m[11] * v.z + m[15] * v.w);
}
inline float4 mat_row(const float* m, int r) { return (float4)(m[r], m[4 + r], m[8 + r], m[12 + r]); }

/* View-space x (or y) of the ray through ndc `n` at distance d: the inverse of
 * ndc = (P00 x + P20 z) / -z for a perspective projection. */
inline float view_coord(float n, float d, float p_diag, float p_off) { return d * (n + p_off) / p_diag; }

/* NDC edges (low, high) of tile `i` of `tile` pixels along an axis of `size`
 * pixels; the last tile ends at the screen's edge. */
inline float2 tile_ndc_span(uint i, uint tile, uint size) {
  return (float2)(2.0f * (float)(i * tile) / (float)size - 1.0f,
                  2.0f * (float)min((i + 1u) * tile, size) / (float)size - 1.0f);
}

/* View-space x and y extent (x0, x1, y0, y1) of the frustum through the NDC
 * rectangle ex (left, right) x ey (bottom, top) between distances zmin and
 * zmax: the extremes lie on the four edge rays at the two distances. */
inline float4 frustum_xy_box(float2 ex, float2 ey, float zmin, float zmax, const float* proj) {
  const float p00 = proj[0], p20 = proj[8], p11 = proj[5], p21 = proj[9];
  return (float4)(fmin(fmin(view_coord(ex.x, zmin, p00, p20), view_coord(ex.x, zmax, p00, p20)),
                       fmin(view_coord(ex.y, zmin, p00, p20), view_coord(ex.y, zmax, p00, p20))),
                  fmax(fmax(view_coord(ex.x, zmin, p00, p20), view_coord(ex.x, zmax, p00, p20)),
                       fmax(view_coord(ex.y, zmin, p00, p20), view_coord(ex.y, zmax, p00, p20))),
                  fmin(fmin(view_coord(ey.x, zmin, p11, p21), view_coord(ey.x, zmax, p11, p21)),
                       fmin(view_coord(ey.y, zmin, p11, p21), view_coord(ey.y, zmax, p11, p21))),
                  fmax(fmax(view_coord(ey.x, zmin, p11, p21), view_coord(ey.x, zmax, p11, p21)),
                       fmax(view_coord(ey.y, zmin, p11, p21), view_coord(ey.y, zmax, p11, p21))));
}

#endif /* ML_COMMON_VIEW_FRUSTUM_CL */
