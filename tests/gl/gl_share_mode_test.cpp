// How GL and CL share buffers, and which devices they run on: the share-mode
// choice, the GL/CL device match and the refusal of software GL beside a GPU
// (pure functions, with made-up devices: no GPU is needed), a refused sharing
// context falling back (test-only hook MANYLIGHTS_TEST_FAIL_SHARING=1) to an
// image equal to the normal path's, and the hand-over passes in the stats.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "gl/GlContext.hpp"
#include "host/util/Error.hpp"
#include "host/util/ImageIO.hpp"
#include "support/RunCommand.hpp"
#include "support/ScopedEnv.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(ShareMode, ChoiceFollowsSharingZeroCopyAndTheVariable) {
  EXPECT_EQ(chooseShareMode("", true, false, "").mode, ShareMode::Interop);
  EXPECT_EQ(chooseShareMode("interop", true, true, "").mode, ShareMode::Interop);
  auto c = chooseShareMode("", false, true, "");
  EXPECT_EQ(c.mode, ShareMode::HostPtr);
  EXPECT_EQ(c.note, "");
  c = chooseShareMode("", false, false, "");
  EXPECT_EQ(c.mode, ShareMode::Copy) << "hostptr only where the zero-copy check passed";
  EXPECT_TRUE(contains(c.note, "not zero-copy")) << c.note;
  c = chooseShareMode("hostptr", false, false, "");
  EXPECT_EQ(c.mode, ShareMode::Copy);
  EXPECT_TRUE(contains(c.note, "MANYLIGHTS_SHARE=hostptr")) << c.note;
  EXPECT_EQ(chooseShareMode("hostptr", false, true, "").mode, ShareMode::HostPtr);
  c = chooseShareMode("copy", false, true, "");
  EXPECT_EQ(c.mode, ShareMode::Copy);
  EXPECT_EQ(c.note, "");
  EXPECT_EQ(chooseShareMode("copy", true, true, "").mode, ShareMode::Copy);
  c = chooseShareMode("", false, true, "the driver refused");
  EXPECT_EQ(c.mode, ShareMode::HostPtr);
  EXPECT_EQ(c.note, "the driver refused: using hostptr mode");
  EXPECT_EQ(chooseShareMode("", false, false, "the driver refused").note, "the driver refused: using copy mode");
}

DeviceInfo device(cl_device_type type) {
  DeviceInfo d;
  d.type = type;
  d.name = type == CL_DEVICE_TYPE_GPU ? "Some GPU" : "pthread-cpu";
  return d;
}

TEST(ShareMode, DeviceMatchByUuidPciOrTheCpu) {
  GlShareHandles gl;
  gl.renderer = "NVIDIA H100/PCIe/SSE2";
  DeviceInfo gpu = device(CL_DEVICE_TYPE_GPU);
  EXPECT_EQ(matchDevices(gl, gpu, true).same, SameDevice::Yes);
  EXPECT_EQ(matchDevices(gl, gpu, false).same, SameDevice::Unknown);
  gl.pci_bus_id = "0000:01:00.0";
  gpu.pci_bus_id = "0000:01:00.0";
  EXPECT_EQ(matchDevices(gl, gpu, false).same, SameDevice::Yes);
  gpu.pci_bus_id = "0000:41:00.0";
  EXPECT_EQ(matchDevices(gl, gpu, false).same, SameDevice::No);
  gl.device_uuid.assign(16, 7);
  gpu.uuid.assign(16, 7);
  EXPECT_EQ(matchDevices(gl, gpu, false).same, SameDevice::Yes) << "UUIDs decide before PCI ids";
  gpu.uuid[15] = 8;
  EXPECT_EQ(matchDevices(gl, gpu, false).same, SameDevice::No);
  EXPECT_EQ(matchDevices(gl, device(CL_DEVICE_TYPE_CPU), false).same, SameDevice::No);
  GlShareHandles sw;
  sw.renderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
  EXPECT_EQ(matchDevices(sw, device(CL_DEVICE_TYPE_CPU), false).same, SameDevice::Yes);
  EXPECT_EQ(matchDevices(sw, device(CL_DEVICE_TYPE_GPU), false).same, SameDevice::No);
  EXPECT_EQ(matchDevices(sw, device(CL_DEVICE_TYPE_CPU), false).text(),
            "same device (software GL and OpenCL both on the CPU)");
}

TEST(ShareMode, SoftwareGlBesideAGpuIsRefusedUnlessAllowed) {
  const test::ScopedEnv clear("MANYLIGHTS_ALLOW_SOFTWARE_GL", nullptr);
  for (const char* r : {"llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe", "Mesa swrast"}) {
    GlShareHandles sw;
    sw.renderer = r;
    try {
      refuseSoftwareGlBesideGpu(sw, device(CL_DEVICE_TYPE_GPU));
      ADD_FAILURE() << r << " beside a GPU was not refused";
    } catch (const UserError& e) {
      EXPECT_TRUE(contains(e.what(), "MANYLIGHTS_ALLOW_SOFTWARE_GL=1")) << e.what();
      EXPECT_TRUE(contains(e.what(), r)) << e.what();
    }
    EXPECT_NO_THROW(refuseSoftwareGlBesideGpu(sw, device(CL_DEVICE_TYPE_CPU))) << "today's PoCL + llvmpipe";
    const test::ScopedEnv allow("MANYLIGHTS_ALLOW_SOFTWARE_GL", "1");
    EXPECT_NO_THROW(refuseSoftwareGlBesideGpu(sw, device(CL_DEVICE_TYPE_GPU)));
  }
  GlShareHandles hw;
  hw.renderer = "AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54, 6.5.0)";
  EXPECT_NO_THROW(refuseSoftwareGlBesideGpu(hw, device(CL_DEVICE_TYPE_GPU)));
}

// The runtime beside this process's GL context: what `render` reports.
TEST(ShareMode, RuntimeBesideTheGlContext) {
  const test::ScopedEnv share("MANYLIGHTS_SHARE", nullptr);
  const GlShareHandles h = test::glContext().shareHandles();
  EXPECT_FALSE(h.renderer.empty());
  auto rt = ClRuntime::create(DeviceChoice::resolve(""), &h);
  if (rt->glSharingActive()) {
    EXPECT_EQ(rt->shareMode(), ShareMode::Interop);
  } else {
    EXPECT_EQ(rt->shareMode(), rt->zeroCopyHostPtr() ? ShareMode::HostPtr : ShareMode::Copy);
  }
  if (rt->info().isCpu()) {
    EXPECT_TRUE(rt->zeroCopyHostPtr()) << "PoCL's host pointers are zero-copy";
  }
  if (isSoftwareRenderer(h.renderer) && rt->info().isCpu()) {
    EXPECT_EQ(rt->deviceMatch().same, SameDevice::Yes);
  }
  EXPECT_TRUE(contains(rt->describe(), "share mode: " + shareModeName(rt->shareMode()))) << rt->describe();
  EXPECT_TRUE(contains(rt->describe(), h.renderer)) << rt->describe();
}

TEST(ShareMode, RefusedSharingFallsBackWithAReason) {
  const GlShareHandles h = test::glContext().shareHandles();
  const test::ScopedEnv hook("MANYLIGHTS_TEST_FAIL_SHARING", "1");
  {
    const test::ScopedEnv share("MANYLIGHTS_SHARE", nullptr);
    auto rt = ClRuntime::create(DeviceChoice::resolve(""), &h);
    EXPECT_FALSE(rt->glSharingActive());
    EXPECT_NE(rt->shareMode(), ShareMode::Interop);
    EXPECT_TRUE(contains(rt->shareNote(), "refused")) << rt->shareNote();
    EXPECT_TRUE(contains(rt->shareNote(), "using " + shareModeName(rt->shareMode()))) << rt->shareNote();
  }
  {
    const test::ScopedEnv share("MANYLIGHTS_SHARE", "copy");  // skips the attempt
    auto rt = ClRuntime::create(DeviceChoice::resolve(""), &h);
    EXPECT_EQ(rt->shareMode(), ShareMode::Copy);
    EXPECT_EQ(rt->shareNote(), "");
  }
  const test::ScopedEnv share("MANYLIGHTS_SHARE", "interop");
  EXPECT_THROW(ClRuntime::create(DeviceChoice::resolve(""), &h), UserError);
}

nlohmann::json renderTiled(const std::string& name, const std::string& env, std::vector<float>& image,
                           std::string* err = nullptr) {
  const std::string png = test::tempDir() + "/" + name + ".png";
  const std::string json = test::tempDir() + "/" + name + ".json";
  auto r = test::runManylights("render --size 96x64 --lights 300 --technique tiled-deferred --out " + png +
                                   " --stats-json " + json,
                               env);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (err) *err = r.err;
  unsigned w = 0, h = 0;
  image = readImageRgba(png, w, h);
  std::ifstream in(json);
  return nlohmann::json::parse(in);
}

TEST(ShareMode, FallbackRendersTheSameImage) {
  std::vector<float> normal, fallback, copy;
  const auto j = renderTiled("normal", "", normal);
  std::string err;
  renderTiled("fallback", "MANYLIGHTS_TEST_FAIL_SHARING=1", fallback, &err);
  EXPECT_TRUE(contains(err, "refused a context sharing with GL")) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "one line saying why: " << err;
  EXPECT_EQ(fallback, normal);
  const auto jc = renderTiled("copy", "MANYLIGHTS_SHARE=copy", copy);
  EXPECT_EQ(copy, normal);
  // The hand-overs are named passes: waits in every mode, copies in copy mode.
  for (const char* pass : {"share-release", "share-copy"}) EXPECT_TRUE(jc["passes"].contains(pass)) << pass;
  if (!contains(j.dump(), "\"share-copy\"")) {
    EXPECT_TRUE(j["passes"].contains("share-acquire")) << j["passes"].dump();
  }
}

TEST(ShareMode, DevicesSaysWhatRenderRunsOn) {
  auto r = test::runManylights("devices");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "render would run")) << r.out;
  EXPECT_TRUE(contains(r.out, "OpenGL: ")) << r.out;
  EXPECT_TRUE(contains(r.out, "share mode: ")) << r.out;
  EXPECT_TRUE(contains(r.out, "same device") || contains(r.out, "different devices") || contains(r.out, "unknown"))
      << r.out;
}

}  // namespace
}  // namespace ml
