/* The window-depth convention, written once for C++, OpenCL C and GLSL: every
 * reader of the depth buffer (kernels, shaders, C++ references, tests) goes
 * through these helpers, so the convention can change in this file alone.
 *
 * Reversed-Z into a 32-bit float depth buffer: clip control
 * (GL_LOWER_LEFT, GL_ZERO_TO_ONE), near -> depth 1, far -> depth 0, cleared
 * to 0 (sky), nearer wins with GL_GREATER. Window depth of view distance z
 * (= -z_view > 0) is d = p32 / z - p22 with p22 = n / (f - n),
 * p32 = n f / (f - n) (host/scene/Camera.cpp). As d falls like n / z, the
 * float's exponent carries the range and every distance keeps ~1e-7 relative
 * precision, for any near (a standard [-1, 1] mapping rounds every depth to 1
 * once near / far drops below ~1e-7). The sum d + p22 adds two positive
 * numbers, so the inversion does not cancel either.
 *
 * GLSL includes this file as "depth_convention.h" (gl/ShaderProgram.cpp
 * looks in host/shared/ too); kernels get it through gpu_types.h, which adds
 * linear_depth(d, cam) on CameraParams. */
#ifndef MANYLIGHTS_DEPTH_CONVENTION_H
#define MANYLIGHTS_DEPTH_CONVENTION_H

#if defined(GL_core_profile)
#define ML_DEPTH_FN
#elif defined(__OPENCL_VERSION__)
#define ML_DEPTH_FN inline
#else
namespace ml::gpu {
#define ML_DEPTH_FN inline
#endif

/* Positive view distance of window depth d. p22, p32: projection elements
 * (row 2, col 2) and (row 2, col 3), i.e. proj[10] and proj[14] column-major. */
ML_DEPTH_FN float depth_to_distance(float d, float p22, float p32) { return p32 / (d + p22); }

/* Window depth of view distance z: the inverse of depth_to_distance. */
ML_DEPTH_FN float distance_to_depth(float z, float p22, float p32) { return p32 / z - p22; }

/* Nothing was drawn at this pixel: the cleared value 0 (NaN counts as sky). */
ML_DEPTH_FN bool is_sky_depth(float d) { return !(d > 0.0f); }

#undef ML_DEPTH_FN
#if !defined(GL_core_profile) && !defined(__OPENCL_VERSION__)
/* The depth buffer's clear value; the depth test that keeps the nearer
 * fragment is GL_GREATER (GL_GEQUAL / GL_EQUAL against a pre-pass). */
inline constexpr float kSkyDepth = 0.0f;
}  // namespace ml::gpu
#endif

#endif /* MANYLIGHTS_DEPTH_CONVENTION_H */
