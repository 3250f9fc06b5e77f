/* The renderer's direct-light model (gl/shaders/common/shading.glsl), declared once
 * for C++ (namespace ml::gpu) and OpenCL C so that voxel light injection and
 * its C++ twin evaluate each light with the same operations:
 *   colour = base * (ML_SHADE_AMBIENT + ML_SHADE_DIRECT * sum_i I_i * w_i),
 *   w_i = clamp(N . L, 0, 1) * clamp(1 - d / r, 0, 1)^2.
 * Scalar code only: OpenCL C and C++ share no vector type. Kernels that
 * include it turn FP_CONTRACT off so that no multiply-add is fused, which
 * keeps them on the twin's roundings. */
#ifndef MANYLIGHTS_SHADING_MODEL_H
#define MANYLIGHTS_SHADING_MODEL_H

#ifndef __OPENCL_VERSION__
#include <cmath>
namespace ml::gpu {
using std::sqrt;
#endif

#define ML_SHADE_AMBIENT 0.1f
#define ML_SHADE_DIRECT 0.9f

/* w_i for a light at (lx, ly, lz) with radius r seen from point p with unit
 * normal n (computeLight in shading.glsl, without the colour). A zero normal
 * (a voxel whose fragments' normals cancel: a sheet seen from both sides)
 * takes the cosine as 1. */
static inline float ml_light_weight(float lx, float ly, float lz, float r, float px, float py, float pz, float nx,
                                    float ny, float nz) {
  float x = lx - px, y = ly - py, z = lz - pz;
  float d = sqrt(x * x + y * y + z * z);
  float inv = d > 1e-20f ? d : 1e-20f;
  x /= inv;
  y /= inv;
  z /= inv;
  float att = 1.0f - d / r;
  att = att < 0.0f ? 0.0f : (att > 1.0f ? 1.0f : att);
  att *= att;
  float c = (nx == 0.0f && ny == 0.0f && nz == 0.0f) ? 1.0f : nx * x + ny * y + nz * z;
  c = c < 0.0f ? 0.0f : (c > 1.0f ? 1.0f : c);
  return c * att;
}

#ifndef __OPENCL_VERSION__
}  // namespace ml::gpu
#endif
#endif
