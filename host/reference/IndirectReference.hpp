#pragma once
// Ray-traced diffuse indirect light on the CPU (Embree 3, TBB): the reference
// voxel cone tracing is measured against. One bounce unless `bounces` says
// more.
//
// Per pixel: the primary hit x of the camera ray through the pixel centre
// (the GL renderer's camera and pixel convention); `samples` cosine-weighted
// directions over x's hemisphere, as two independent replicas of about
// samples/2 each (each Latin-hypercube stratified in both dimensions; two, so
// that their difference estimates the pixel's noise), seeded per pixel from
// `seed`, so the image does not depend on thread scheduling; at each secondary hit y the direct diffuse radiance of
// the renderer's shading model (gl/shaders/common/shading.glsl, without its ambient
// term and 0.9 weight):
//     B(y) = albedo(y) * sum_i I_i * max(0, n_y . l_i) * clamp(1 - d_i / r_i, 0, 1)^2
// optionally only over lights visible from y (a shadow ray each); then
//     indirect(x) = albedo(x) * mean over the samples of B(y)
// (the cosine-weighted estimate of albedo/pi * integral of B cos). With
// bounces = k > 1 each sample's path goes on from y: one cosine-weighted
// direction from y to z adds albedo(y) * B(z), from z the next, k - 1 times
// in all (light that bounced k times before x; a path that leaves the scene
// adds nothing more). Normals are
// the interpolated vertex normals, turned to the side of the surface (by its
// geometric normal) that the ray arrived on; albedo is the material's base colour times its texture (bilinear,
// level 0, the bytes as GL samples them). Misses contribute 0.
#include <cstdint>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/Scene.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/ThesisSeed.hpp"

namespace ml {

struct IndirectOptions {
  unsigned samples = 64;      // hemisphere samples per pixel, >= 1
  std::uint64_t seed = kThesisSeed;
  bool shadow_rays = false;   // visibility of the lights from the secondary hits (every hit of a path)
  unsigned bounces = 1;       // 1..kMaxIndirectBounces
};

struct IndirectImage {
  unsigned width = 0, height = 0;
  // Linear RGBA, rows bottom-up (GL order); alpha 1 where the pixel sees the
  // scene, 0 where it sees nothing (rgb 0 there).
  std::vector<float> rgba;
  // Per pixel, the estimated variance of its rgb mean (summed over rgb): the
  // reference's own noise, from the pixel's two replica means A and B as
  // (A - B)^2 / 4 (replicaVariance in the .cpp); empty with one sample.
  std::vector<float> noise_var;
  double ms = 0;  // wall time of the trace (scene build included), or of reading it from the cache
};

inline constexpr unsigned kMaxIndirectBounces = 8;

// Throws UserError for samples == 0, bounces outside 1..kMaxIndirectBounces
// or a zero-sized image.
IndirectImage traceIndirectReference(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                     const Camera& camera, unsigned width, unsigned height,
                                     const IndirectOptions& options);

// Relative RMSE of an indirect image against a reference image of the same
// format and size (RGBA, alpha > 0 where covered), over the pixels covered in
// both, RGB: sqrt(sum (a - r)^2 / sum r^2). Covered pixels of one image that the
// other does not cover (silhouettes) count in `mismatched`. -1 when the
// reference is black over the common pixels; throws std::invalid_argument on
// sizes that differ.
struct IndirectError {
  double rel_rmse = -1;
  std::size_t pixels = 0;      // covered in both
  std::size_t mismatched = 0;  // covered in one only
};
IndirectError indirectRelRmse(const std::vector<float>& image, const std::vector<float>& reference);

// The error of `image` against a traced reference, with the reference's own
// noise taken out. For an estimate R of the truth T with independent noise,
// E|V - R|^2 = |V - T|^2 + E|R - T|^2, so over the pixels covered in both:
//   ref_noise = sqrt(sum noise_var / sum R^2)        (the noise's relative RMSE)
//   corrected = sqrt(max(0, rel_rmse^2 - ref_noise^2)) (the error against T)
// A better image can show below the reference's noise only in `corrected`.
struct IndirectComparison {
  IndirectError error;
  double ref_noise = -1;  // -1 when the reference is black or has no noise estimate
  double corrected = -1;
};
IndirectComparison compareWithReference(const std::vector<float>& image, const IndirectImage& reference);

}  // namespace ml
