// OpenCL runtime: device discovery, program cache, build errors with logs.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstddef>
#include <filesystem>

#include "host/cl/ClRuntime.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/shared/gpu_types.h"
#include "host/util/Error.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

TEST(ClRuntime, ListsAtLeastOneDevice) {
  auto devices = listDevices();
  ASSERT_FALSE(devices.empty());
  for (const auto& d : devices) {
    EXPECT_FALSE(d.info.name.empty());
    EXPECT_GT(d.info.compute_units, 0u);
    EXPECT_GT(d.info.max_work_group_size, 0u);
  }
}

TEST(ClRuntime, DeviceChoiceParsing) {
  EXPECT_EQ(DeviceChoice::parse("gpu", "--device").kind, DeviceChoice::Kind::Gpu);
  EXPECT_EQ(DeviceChoice::parse("cpu", "--device").kind, DeviceChoice::Kind::Cpu);
  auto idx = DeviceChoice::parse("0", "--device");
  EXPECT_EQ(idx.kind, DeviceChoice::Kind::Index);
  EXPECT_EQ(idx.index, 0);
  EXPECT_THROW(DeviceChoice::parse("-1", "--device"), UserError);
  EXPECT_THROW(DeviceChoice::parse("+1", "--device"), UserError);
  try {
    DeviceChoice::parse("1x", "MANYLIGHTS_DEVICE");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("MANYLIGHTS_DEVICE"), std::string::npos);
  }
  // Anything else is a name, matched when the runtime is created.
  for (const char* name : {"rusticl", "PoCL", "llvmpipe", "x1"}) {
    const auto c = DeviceChoice::parse(name, "--device");
    EXPECT_EQ(c.kind, DeviceChoice::Kind::Name) << name;
    EXPECT_EQ(c.name, name);
  }
}

// Made-up devices as PoCL and rusticl (with llvmpipe) list themselves, plus a
// second device of one platform.
std::vector<DeviceInfo> fakeDevices() {
  auto info = [](std::string platform, std::string vendor, std::string name) {
    DeviceInfo d;
    d.platform_name = std::move(platform);
    d.platform_vendor = std::move(vendor);
    d.name = std::move(name);
    return d;
  };
  return {info("Portable Computing Language", "The pocl project", "cpu-haswell-Intel(R) Xeon(R)"),
          info("rusticl", "Mesa/X.org", "llvmpipe (LLVM 15.0.6, 256 bits)"),
          info("NVIDIA CUDA", "NVIDIA Corporation", "NVIDIA H100 80GB HBM3"),
          info("NVIDIA CUDA", "NVIDIA Corporation", "NVIDIA A100")};
}

TEST(ClRuntime, DeviceNameMatchesPlatformNameVendorOrDeviceIgnoringCase) {
  const auto devices = fakeDevices();
  EXPECT_EQ(deviceIndexByName(devices, "pocl", "--device"), 0u);      // platform vendor
  EXPECT_EQ(deviceIndexByName(devices, "Portable", "--device"), 0u);  // platform name
  EXPECT_EQ(deviceIndexByName(devices, "RUSTICL", "--device"), 1u);
  EXPECT_EQ(deviceIndexByName(devices, "mesa", "--device"), 1u);
  EXPECT_EQ(deviceIndexByName(devices, "LLVMpipe", "--device"), 1u);  // device name
  EXPECT_EQ(deviceIndexByName(devices, "h100", "--device"), 2u);
}

// One line naming the flag or variable and listing every device to choose from.
void expectNameError(const std::string& name, const std::string& origin, const std::string& why) {
  try {
    deviceIndexByName(fakeDevices(), name, origin);
    ADD_FAILURE() << name << " was accepted";
  } catch (const UserError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(origin + " '" + name + "'", 0), 0u) << msg;
    EXPECT_NE(msg.find(why), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const char* listed : {"0: Portable Computing Language", "1: rusticl (Mesa/X.org) / llvmpipe", "3: NVIDIA CUDA"})
      EXPECT_NE(msg.find(listed), std::string::npos) << listed << " not in: " << msg;
  }
}

TEST(ClRuntime, AmbiguousOrUnknownDeviceNameIsAUserErrorListingTheDevices) {
  expectNameError("nvidia", "--device", "more than one");
  expectNameError("l", "MANYLIGHTS_DEVICE", "more than one");
  expectNameError("radeon", "MANYLIGHTS_DEVICE", "matches no OpenCL device");
}

// The same through the real device list: a name matching nothing here.
TEST(ClRuntime, UnknownDeviceNameFailsCreation) {
  try {
    ClRuntime::create(DeviceChoice::parse("no-such-opencl-device", "MANYLIGHTS_DEVICE"));
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("MANYLIGHTS_DEVICE 'no-such-opencl-device': matches no OpenCL device", 0), 0u) << msg;
    EXPECT_NE(msg.find("0: " + listDevices().front().info.platform_name), std::string::npos) << msg;
  }
}

// Each device found by its own device name, unless another shares it.
TEST(ClRuntime, EveryDeviceIsFoundByAUniqueName) {
  const auto devices = listDevices();
  for (const auto& d : devices) {
    int same = 0;
    for (const auto& o : devices) same += o.info.name == d.info.name;
    if (same > 1) continue;
    auto rt = ClRuntime::create(DeviceChoice::parse(d.info.name, "--device"));
    EXPECT_EQ(rt->info().name, d.info.name);
    EXPECT_EQ(rt->info().platform_name, d.info.platform_name);
  }
}

// The error names where the index came from: the flag or the variable.
TEST(ClRuntime, OutOfRangeIndexIsAUserErrorNamingItsOrigin) {
  for (const char* origin : {"--device", "MANYLIGHTS_DEVICE"}) {
    try {
      ClRuntime::create(DeviceChoice::parse("999", origin));
      ADD_FAILURE() << origin << ": device 999 was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string(origin) + " 999:", 0), 0u) << e.what();
    }
  }
}

TEST(ClRuntime, DescribeNamesDevice) {
  auto& rt = test::runtime();
  EXPECT_NE(rt.describe().find(rt.info().name), std::string::npos);
}

TEST(ProgramBuilder, SecondBuildHitsDiskCache) {
  auto dir = std::filesystem::temp_directory_path() / ("ml-cache-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  ::setenv("MANYLIGHTS_CACHE_DIR", dir.c_str(), 1);
  // A source unique to this run so no earlier cache entry can exist.
  const std::string src = "__kernel void k(__global int* a) { a[get_global_id(0)] = " +
                          std::to_string(std::rand()) + "; }\n";
  // A driver that ends the process when it refuses a binary (rusticl) gets
  // none (host/cl/KernelCacheProbe.hpp): there the second build compiles too.
  bool caches = false;
  {
    auto rt = ClRuntime::create(DeviceChoice::resolve(""));
    caches = rt->programs().cachesBinaries();
    rt->programs().buildSource("cache_probe.cl", src);
    EXPECT_EQ(rt->programs().stats().compiles, 1);
    EXPECT_EQ(rt->programs().stats().disk_hits, 0);
  }
  {
    auto rt = ClRuntime::create(DeviceChoice::resolve(""));
    cl::Program p = rt->programs().buildSource("cache_probe.cl", src);
    EXPECT_EQ(rt->programs().stats().compiles, caches ? 0 : 1);
    EXPECT_EQ(rt->programs().stats().disk_hits, caches ? 1 : 0);
    // The cached program still runs.
    cl::Buffer buf(rt->context(), CL_MEM_READ_WRITE, 4 * sizeof(int));
    cl::Kernel k(p, "k");
    k.setArg(0, buf);
    rt->queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(4));
    int out[4] = {};
    rt->queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof out, out);
    EXPECT_EQ(out[3], std::stoi(src.substr(src.find("= ") + 2)));
    // Different defines are a different entry.
    rt->programs().buildSource("cache_probe.cl", src, {{"UNUSED", "1"}});
    EXPECT_EQ(rt->programs().stats().compiles, caches ? 1 : 2);
  }
  ::unsetenv("MANYLIGHTS_CACHE_DIR");
  std::filesystem::remove_all(dir);
}

TEST(ProgramBuilder, BuildErrorCarriesLog) {
  auto& rt = test::runtime();
  try {
    rt.programs().buildSource("broken.cl", "__kernel void k(__global int* a) { a[0] = undeclared_name; }\n");
    FAIL() << "expected a build failure";
  } catch (const UserError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("broken.cl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undeclared_name"), std::string::npos) << "log missing: " << msg;
  }
}

TEST(ProgramBuilder, ExpandsSharedHeader) {
  auto text = ProgramBuilder::expandIncludes("t.cl", "#include \"gpu_types.h\"\nint x;\n");
  EXPECT_NE(text.find("typedef struct PointLight"), std::string::npos);
  EXPECT_THROW(ProgramBuilder::expandIncludes("t.cl", "#include \"nope.h\"\n"), UserError);
}

TEST(ProgramBuilder, SharedStructLayoutMatchesDevice) {
  auto& rt = test::runtime();
  cl::Program p = rt.programs().buildSource("layout.cl",
      "#include \"gpu_types.h\"\n"
      "__kernel void sizes(__global uint* out) {\n"
      "  out[0] = sizeof(PointLight); out[1] = sizeof(LightRange); out[2] = sizeof(CameraParams);\n"
      "  CameraParams c; PointLight l;\n"
      "  out[3] = (uint)((char*)&c.near_plane - (char*)&c); out[4] = (uint)((char*)&l.color - (char*)&l);\n"
      "}\n");
  cl::Buffer buf(rt.context(), CL_MEM_WRITE_ONLY, 5 * sizeof(cl_uint));
  cl::Kernel k(p, "sizes");
  k.setArg(0, buf);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1));
  cl_uint out[5] = {};
  rt.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof out, out);
  EXPECT_EQ(out[0], sizeof(gpu::PointLight));
  EXPECT_EQ(out[1], sizeof(gpu::LightRange));
  EXPECT_EQ(out[2], sizeof(gpu::CameraParams));
  EXPECT_EQ(out[3], offsetof(gpu::CameraParams, near_plane));
  EXPECT_EQ(out[4], offsetof(gpu::PointLight, color));
}

}  // namespace
}  // namespace ml
