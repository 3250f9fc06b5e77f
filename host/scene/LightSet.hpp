#pragma once
// Point-light sets: seeded generation inside "light generation volumes" (boxes,
// as in the hashed-shading thesis), and JSON load/save.
//
// JSON format (manylights): {"lights": [{"position": [x,y,z], "radius": r,
// "intensity": [r,g,b]}, ...]}. The nTiled suite's light files
// ({"lights": [{"position": {...}|[...], "intensity": ..., "radius": ...}]})
// load through the same function.
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/shared/gpu_types.h"
#include "host/util/ThesisSeed.hpp"

namespace ml {

struct LightVolume {
  glm::vec3 min{0.0f};
  glm::vec3 max{1.0f};
  float weight = 1.0f;  // relative share of the lights placed in this box
};

struct LightGenParams {
  std::uint32_t count = 0;
  float radius = 1.0f;           // every light gets this radius ...
  float radius_jitter = 0.0f;    // ... times a uniform factor in [1 - j, 1 + j]
  std::uint64_t seed = 1;
  // Colours are fully saturated random hues (HSV with S = V = 1), as in the thesis.
};

// Same seed and volumes give the same lights on every platform: the generator
// draws from std::mt19937_64 through its own (specified) uniform mapping, not
// the implementation-defined std:: distributions. Per light, in order: box
// (by weight), x, y, z, hue, radius jitter. Throws UserError for unusable input
// (no volumes or no positive weight while count > 0, inverted boxes, radius <= 0,
// jitter outside [0, 1)).
std::vector<gpu::PointLight> generateLights(const std::vector<LightVolume>& volumes, const LightGenParams& params);

// A scene's light-generation volumes plus the generation parameters suggested
// for it. JSON: {"volumes": [{"min": [x,y,z], "max": [x,y,z], "weight": w}, ...],
// "radius": r, "radius_jitter": j, "seed": s, "count": n}; everything but
// "volumes" is optional and fills `defaults` (count/seed are those the scene's
// shipped light file was generated with). "surface_inset": d (default 0) says
// the boxes stay d inside the surfaces that bound them (floors, walls):
// constant-density sets grow the boxes by d so that small lights still reach
// those surfaces (densityRadius).
struct LightVolumeSet {
  std::vector<LightVolume> volumes;  // never empty after loading
  LightGenParams defaults;
  float surface_inset = 0.0f;
};
LightVolumeSet loadLightVolumesJson(const std::string& path);

// Constant-density light sets (--light-density K): the radius for which
// `count` lights keep about K lights on each covered pixel's surface point
// (the mean exact lower bound per covered pixel), so that it falls as
// count^(-1/3). Chosen analytically, once, from the volumes, no frame needed:
//  - lights are uniform in the volumes' total volume V (boxes with weight > 0;
//    overlaps counted twice), so a point inside them lies in
//    count / V * 4/3 pi E[r^3] spheres on average, whatever the weights
//    (the mean over V of the per-box densities), and E[r^3] = r^3 (1 + j^2)
//    for the jitter j's uniform factor in [1 - j, 1 + j];
//  - visible surfaces (floors, walls, ceilings) bound the volumes (grown by
//    the file's surface_inset, so that they do at any radius), where a
//    sphere keeps about half its volume inside: kSurfaceCoverage.
//   K = kSurfaceCoverage * count / V * 4/3 pi r^3 (1 + j^2), solved for r.
// Measured on data/default at 1920x1080 (docs/scaling.md, "Scaling to a million
// lights"): the mean lower bound per covered pixel is 1.1..1.35 K from 1k to
// 1M lights.
constexpr double kSurfaceCoverage = 0.5;
float densityRadius(const std::vector<LightVolume>& volumes, std::uint64_t count, float density, float jitter);

// " at density K (mean r R)" for a generated set's label; "" when density is 0.
std::string densityLabel(float density, const std::vector<gpu::PointLight>& lights);
// UserError naming --light-density when it is given with --light-radius or
// for lights that are not generated (light files carry their own radii).
void checkLightDensityFlag(float density, float radius, bool generated);

// `count` lights in the volumes of `volumes_path` with its suggested radius
// and jitter; without a file, uniformly in the box [lo, hi] with radius 1/20
// of its largest side (no jitter). radius > 0 overrides either radius;
// density > 0 (exclusive with radius) sets it with densityRadius().
std::vector<gpu::PointLight> generateLightsIn(const std::string& volumes_path, glm::vec3 lo, glm::vec3 hi,
                                              std::uint32_t count, std::uint64_t seed, float radius,
                                              float density = 0.0f);

// Throws UserError naming the file on missing file, bad JSON or bad fields
// (non-positive radius, wrong array lengths, non-finite numbers).
std::vector<gpu::PointLight> loadLightsJson(const std::string& path);
void saveLightsJson(const std::string& path, const std::vector<gpu::PointLight>& lights);

// Light-count limits, checked before lights are generated or loaded into a
// renderer (docs/usage.md, "Bad input"):
//  - kMaxLights: the most lights any technique takes. A ceiling well inside
//    the 32-bit light indices, counts and sort keys used throughout, at 4 GiB
//    of light data (32 bytes each), more than one buffer of common OpenCL
//    devices holds (PoCL: 2 GiB, CL_DEVICE_MAX_MEM_ALLOC_SIZE).
//  - kHostBytesPerLight: host memory a run needs per light, from measured peak
//    resident sizes at 1M lights (PoCL + llvmpipe, where device buffers are host
//    memory too): 185 (brute force, hashed) to 370 (tiled) bytes, rounded up for
//    --animate's copies of the light set.
//  - kDeviceBytesPerLight: device memory per light: the light buffer and the
//    per-light arrays of the techniques (bounds, sort keys, sorted copies).
constexpr std::uint64_t kMaxLights = std::uint64_t(1) << 27;
constexpr std::uint64_t kHostBytesPerLight = 512;
constexpr std::uint64_t kDeviceBytesPerLight = 128;

// Host memory this process may still use, in bytes: the smaller of the
// system's available memory (/proc/meminfo MemAvailable) and what the
// address-space limit (ulimit -v) leaves; UINT64_MAX when neither is known.
std::uint64_t availableHostMemory();

// UserError naming `flag` (one line, with the limit) when `count` lights
// exceed kMaxLights or kHostBytesPerLight x count exceeds availableHostMemory().
// `what` says where the count comes from ("generated", a file name).
void checkLightCount(const std::string& flag, std::uint64_t count, const std::string& what = "");

inline gpu::PointLight makeLight(glm::vec3 p, float radius, glm::vec3 color) {
  gpu::PointLight l{};
  l.position_radius = {p.x, p.y, p.z, radius};
  l.color = {color.x, color.y, color.z, 0.0f};
  return l;
}

}  // namespace ml
