/* Plain data shared by the host (C++20) and the kernels (OpenCL C 1.2), declared
 * once. Kernels include it as `#include "gpu_types.h"` (resolved by
 * ProgramBuilder from the embedded copy); C++ includes "host/shared/gpu_types.h"
 * and sees the same structs in namespace ml::gpu, with static size checks.
 * GLSL mirrors these layouts in std430 blocks (see gl/shaders/common/common.glsl). */
#ifndef MANYLIGHTS_GPU_TYPES_H
#define MANYLIGHTS_GPU_TYPES_H

#include "depth_convention.h"

#ifdef __OPENCL_VERSION__
typedef float4 ml_float4;
typedef uint ml_uint;
typedef int ml_int;
#define ML_STATIC_ASSERT(cond, msg)
#else
#include <cstdint>
namespace ml::gpu {
struct alignas(16) ml_float4 {
  float x, y, z, w;
};
typedef std::uint32_t ml_uint;
typedef std::int32_t ml_int;
#define ML_STATIC_ASSERT(cond, msg) static_assert(cond, msg)
#endif

/* A finite point light. position_radius = (x, y, z, radius) in world space;
 * color = (r, g, b, unused) intensity, each in [0, 1] by convention. */
typedef struct PointLight {
  ml_float4 position_radius;
  ml_float4 color;
} PointLight;
ML_STATIC_ASSERT(sizeof(PointLight) == 32, "PointLight must be 32 bytes (std430 vec4 pair)");
ML_STATIC_ASSERT(alignof(PointLight) == 16, "PointLight must be 16-byte aligned");

/* One tile's or cluster's list: a range of entries (tiled: light indices;
 * clustered: hit records, see kernels/clustered/cluster_assign.cl). */
typedef struct LightRange {
  ml_uint offset;
  ml_uint count;
} LightRange;
ML_STATIC_ASSERT(sizeof(LightRange) == 8, "LightRange must be 8 bytes (std430 uvec2)");

/* Camera data the culling kernels need. Matrices are column-major (glm / GLSL
 * convention): element (row r, col c) is at m[c * 4 + r]. */
typedef struct CameraParams {
  float view[16];
  float proj[16];
  float near_plane;
  float far_plane;
  float tan_half_fovy;
  float aspect;
  ml_uint width;
  ml_uint height;
  ml_uint pad0;
  ml_uint pad1;
} CameraParams;
ML_STATIC_ASSERT(sizeof(CameraParams) == 160, "CameraParams layout changed: update kernels and GLSL");

/* Positive view distance (-z_view) of window depth d under this camera's
 * projection; the convention lives in depth_convention.h. */
#ifdef __OPENCL_VERSION__
inline float linear_depth(float d, const CameraParams* cam) {
  return depth_to_distance(d, cam->proj[10], cam->proj[14]);
}
#else
inline float linear_depth(float d, const CameraParams& cam) { return depth_to_distance(d, cam.proj[10], cam.proj[14]); }
#endif
/* The exact lower bound (kernels/assign/exact_lower_bound.cl): the frame's inverse
 * view matrix and projection (column-major, as uploaded to the shaders) and viewport. */
typedef struct BoundParams {
  float inv_view[16];
  float proj[16];
  ml_uint width;
  ml_uint height;
  ml_uint level_count;  /* BoundGridLevel entries */
  ml_uint pad0;
} BoundParams;
ML_STATIC_ASSERT(sizeof(BoundParams) == 144, "BoundParams layout changed: update exact_lower_bound.cl");

/* One level of the lower bound's light grid: a dense grid of cubic cells;
 * cell (x, y, z) is global cell first_cell + x + nx * (y + ny * z). */
typedef struct BoundGridLevel {
  float origin_cell[4];  /* origin x, y, z; cell edge length */
  ml_uint dims[4];       /* nx, ny, nz, first_cell */
} BoundGridLevel;
ML_STATIC_ASSERT(sizeof(BoundGridLevel) == 32, "BoundGridLevel layout changed: update exact_lower_bound.cl");

#ifndef __OPENCL_VERSION__
}  // namespace ml::gpu
#endif

#endif /* MANYLIGHTS_GPU_TYPES_H */
