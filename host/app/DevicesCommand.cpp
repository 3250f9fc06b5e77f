#include "host/app/DevicesCommand.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include "gl/GlContext.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelCacheProbe.hpp"
#include "host/util/Error.hpp"

namespace ml {

namespace {

// "pass times: ... | binaries: ..." for one device; both need a context on it.
std::string measuredTraits(const DeviceListing& d) {
  try {
    const cl::Context context(d.device);
    const bool clock = deviceProfilingWorks(context, d.device);
    const std::string key = d.info.platform_name + "|" + d.info.platform_version + "|" + d.info.name + "|" +
                            d.info.version + "|" + d.info.driver_version;
    const bool binaries = driverRefusesBinariesSafely(d.device, key);
    return std::string(" | pass times: ") +
           (clock ? "device clock" : "host clock (the device's profiling clock is unusable)") +
           " | program binaries: " + (binaries ? "cached" : kUnsafeBinariesReason);
  } catch (const cl::Error& e) {
    return " | no context: " + describeClError(e);
  }
}

void printPlatforms() {
  for (const auto& p : listPlatforms()) {
    std::printf("platform %s (%s), %s%s\n", p.name.c_str(), p.vendor.c_str(), p.version.c_str(),
                p.devices.empty() ? ": no devices" : "");
    for (const auto& d : p.devices)
      std::printf("  %d: %s | %s, %u compute units, %s%s%s\n", d.index, d.info.name.c_str(),
                  d.info.isGpu() ? "GPU" : d.info.isCpu() ? "CPU" : "other", d.info.compute_units,
                  d.info.c_version.c_str(), d.info.hasExtension("cl_khr_gl_sharing") ? ", cl_khr_gl_sharing" : "",
                  measuredTraits(d).c_str());
  }
}

}  // namespace

int runDevices() {
  printPlatforms();
  listDevices();  // no device at all: the UserError naming the package to install
  std::unique_ptr<GlContext> gl;
  try {
    gl = createHeadlessContext();
  } catch (const UserError& e) {
    std::printf("render would run: no GL context (%s)\n", e.what());
    return 0;
  }
  const GlShareHandles share = gl->shareHandles();
  auto cl = ClRuntime::create(DeviceChoice::resolve(""), &share);
  std::printf("render would run:\n  %s\n  %s\n", gl->describe().c_str(), cl->describe().c_str());
  return 0;
}

}  // namespace ml
