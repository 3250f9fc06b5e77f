#include "host/run/InputChecks.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "host/run/RunRecords.hpp"
#include "host/scene/LightSet.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/Error.hpp"

namespace ml {
namespace {

std::string mib(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f MiB", bytes / (1024.0 * 1024.0));
  return buf;
}

}  // namespace

CLI::Validator finitePositive() {
  return CLI::Validator(
      [](std::string& text) {
        float v = 0;
        const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        const bool ok = ec == std::errc() && p == text.data() + text.size() && v > 0.0f && std::isfinite(v);
        return ok ? std::string() : "expected a finite number > 0, got '" + text + "'";
      },
      "NUMBER>0");
}

void checkLightLimits(const std::string& flag, std::uint64_t count, const std::vector<const TechniqueInfo*>& techs,
                      const std::string& what) {
  if (count > kMaxLights) checkLightCount(flag, count, what);  // the general maximum first
  for (const TechniqueInfo* t : techs)
    if (count > t->max_lights)
      throw UserError(flag + ": " + t->name + " takes at most " + std::to_string(t->max_lights) + " lights, got " +
                      std::to_string(count) + (what.empty() ? "" : " (" + what + ")"));
  checkLightCount(flag, count, what);
}

void checkDeviceLightLimits(const std::string& flag, std::uint64_t count, const DeviceInfo& device) {
  const double buffer = double(count) * sizeof(gpu::PointLight);
  if (device.max_alloc_size > 0 && buffer > double(device.max_alloc_size))
    throw UserError(flag + ": " + std::to_string(count) + " lights need a " + mib(buffer) + " light buffer; " +
                    device.name + " allocates at most " + mib(double(device.max_alloc_size)) +
                    " per buffer (CL_DEVICE_MAX_MEM_ALLOC_SIZE)");
  const double need = double(count) * double(kDeviceBytesPerLight);
  if (device.global_mem_size > 0 && need > double(device.global_mem_size))
    throw UserError(flag + ": " + std::to_string(count) + " lights need about " + mib(need) + " of device memory (" +
                    std::to_string(kDeviceBytesPerLight) + " bytes each); " + device.name + " has " +
                    mib(double(device.global_mem_size)));
}

}  // namespace ml
