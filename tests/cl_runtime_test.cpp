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
  EXPECT_THROW(DeviceChoice::parse("fast", "--device"), UserError);
  EXPECT_THROW(DeviceChoice::parse("-1", "--device"), UserError);
  try {
    DeviceChoice::parse("x1", "MANYLIGHTS_DEVICE");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("MANYLIGHTS_DEVICE"), std::string::npos);
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
  {
    auto rt = ClRuntime::create(DeviceChoice::resolve(""));
    rt->programs().buildSource("cache_probe.cl", src);
    EXPECT_EQ(rt->programs().stats().compiles, 1);
    EXPECT_EQ(rt->programs().stats().disk_hits, 0);
  }
  {
    auto rt = ClRuntime::create(DeviceChoice::resolve(""));
    cl::Program p = rt->programs().buildSource("cache_probe.cl", src);
    EXPECT_EQ(rt->programs().stats().compiles, 0);
    EXPECT_EQ(rt->programs().stats().disk_hits, 1);
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
    EXPECT_EQ(rt->programs().stats().compiles, 1);
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
