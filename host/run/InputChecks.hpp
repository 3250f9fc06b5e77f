#pragma once
// Flag checks the commands run before any scene is loaded or GL/CL opens, so a
// bad flag is one line naming it (exit 2) and no start-up line comes first.
// Limits that need the device (its buffer sizes) are checked as soon as it is
// open, still before the first frame.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/run/SceneInputs.hpp"  // parseLightCount
#include "host/techniques/Registry.hpp"
#include "host/cl/ClRuntime.hpp"

namespace ml {

// A CLI11 check for flags that take a finite number > 0 (--light-radius): it
// runs only when the flag is given, so an unset flag keeps its default while
// 0, -1, nan and inf are refused naming the flag.
CLI::Validator finitePositive();

// Help of --light-density (render, bench, the bench mains); the constant is
// explained at densityRadius() in host/scene/LightSet.hpp.
inline constexpr const char* kLightDensityHelp =
    "generated lights at constant density: radius scaled as N^(-1/3) so that about K lights cover each visible "
    "surface point (mean exact lower bound per covered pixel), from the light volumes' total volume V: "
    "K = 0.5 N/V 4/3 pi r^3 (1+jitter^2), 0.5 for surfaces bounding the volumes; not with --light-radius";

// The hard light-count limits, for the --lights help of render and bench
// (docs/scaling.md): kMaxLights and kHostBytesPerLight
// (LightSet.hpp), hashed::kMaxHashedLights and the octree's build-memory limit
// (host/hashed/OctreeBounds.hpp), checkDeviceLightLimits. Every other structure
// grows with its lists.
inline constexpr const char* kLightLimitsHelp =
    "Limits: 2^27 lights; about 512 bytes of host memory per light; the light buffer within the device's largest "
    "allocation. hashed: 2^24-1 lights, and its octree build within 1 GiB (constant density on data/default: "
    "--node-size 0.5r holds 1M lights); refused with one line before or at the build, never cut.";

inline constexpr const char* kNoShadingHelp =
    "skip the shading pass: depth and light-assignment passes only, to measure assignment without paying for "
    "shading; counts then give the exact lower bound but no light evaluations (reports say 'shaded: false')";

// `count` lights against kMaxLights, the host memory estimate and the limit of
// every technique in `techs` (hashed: 2^24-1): one line naming `flag`.
void checkLightLimits(const std::string& flag, std::uint64_t count, const std::vector<const TechniqueInfo*>& techs,
                      const std::string& what = "");

// Once the device is open: the light buffer against its largest allocation
// (CL_DEVICE_MAX_MEM_ALLOC_SIZE) and kDeviceBytesPerLight x count against its
// global memory.
void checkDeviceLightLimits(const std::string& flag, std::uint64_t count, const DeviceInfo& device);

}  // namespace ml
