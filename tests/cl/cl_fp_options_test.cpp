// Programs build with -cl-fp32-correctly-rounded-divide-sqrt exactly where
// the device offers CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT; where it does not
// (forced here by the test-only MANYLIGHTS_TEST_INEXACT_DIVIDE hook), the
// kernel-vs-twin tests fall back to the stated tolerance of
// tests/support/FpTolerance.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "host/cl/ProgramBuilder.hpp"
#include "support/FpTolerance.hpp"
#include "support/ScopedEnv.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

constexpr const char* kFlag = "-cl-fp32-correctly-rounded-divide-sqrt";

bool hasFlag(const std::string& options) { return options.find(kFlag) != std::string::npos; }

TEST(ClFpOptions, FlagFollowsTheDeviceFpConfig) {
  test::ScopedEnv clear("MANYLIGHTS_TEST_INEXACT_DIVIDE", nullptr);
  EXPECT_EQ(baseBuildOptions(cl_device_fp_config(0)), "-cl-std=CL1.2");
  EXPECT_EQ(baseBuildOptions(CL_FP_ROUND_TO_NEAREST | CL_FP_INF_NAN), "-cl-std=CL1.2");
  EXPECT_EQ(baseBuildOptions(CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT), std::string("-cl-std=CL1.2 ") + kFlag);
  EXPECT_TRUE(correctlyRoundedDivideSqrt(CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT | CL_FP_FMA));
  const test::ScopedEnv hook("MANYLIGHTS_TEST_INEXACT_DIVIDE", "1");
  EXPECT_FALSE(correctlyRoundedDivideSqrt(CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT));
  EXPECT_EQ(baseBuildOptions(CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT), "-cl-std=CL1.2");
}

constexpr const char* kKernel =
    "__kernel void div_sqrt(__global const float* a, __global const float* b, __global float* q,\n"
    "                       __global float* r, uint n) {\n"
    "  const uint i = get_global_id(0);\n"
    "  if (i < n) { q[i] = a[i] / b[i]; r[i] = sqrt(a[i]); }\n"
    "}\n";

// Builds and runs the kernel; returns the options the program was built with.
std::string runDivSqrt(const std::vector<float>& a, const std::vector<float>& b, std::vector<float>& q,
                       std::vector<float>& r) {
  ClRuntime& rt = test::runtime();
  cl::Program p = rt.programs().buildSource("fp_options_test.cl", kKernel);
  const std::size_t n = a.size();
  cl::Buffer ab(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 4, const_cast<float*>(a.data()));
  cl::Buffer bb(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * 4, const_cast<float*>(b.data()));
  cl::Buffer qb(rt.context(), CL_MEM_WRITE_ONLY, n * 4), rb(rt.context(), CL_MEM_WRITE_ONLY, n * 4);
  cl::Kernel k(p, "div_sqrt");
  k.setArg(0, ab);
  k.setArg(1, bb);
  k.setArg(2, qb);
  k.setArg(3, rb);
  k.setArg(4, cl_uint(n));
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
  q.resize(n);
  r.resize(n);
  rt.queue().enqueueReadBuffer(qb, CL_TRUE, 0, n * 4, q.data());
  rt.queue().enqueueReadBuffer(rb, CL_TRUE, 0, n * 4, r.data());
  return p.getBuildInfo<CL_PROGRAM_BUILD_OPTIONS>(rt.device());
}

// Both paths on this device: the flag where offered, exact results then; with
// the hook, no flag and results within the tolerance.
TEST(ClFpOptions, ProgramsCarryTheFlagAndDivideAsStated) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(1e-3f, 1e3f);
  std::vector<float> a(4099), b(a.size()), q, r;
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = u(rng);
    b[i] = u(rng);
  }
  const bool offered = (test::runtime().info().single_fp_config & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
  for (const char* hook : {static_cast<const char*>(nullptr), "1"}) {
    SCOPED_TRACE(hook ? "MANYLIGHTS_TEST_INEXACT_DIVIDE=1" : "no hook");
    const test::ScopedEnv env("MANYLIGHTS_TEST_INEXACT_DIVIDE", hook);
    const bool exact = test::exactDivideSqrt();
    EXPECT_EQ(exact, offered && !hook);
    EXPECT_EQ(hasFlag(runDivSqrt(a, b, q, r)), exact);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_TRUE(test::floatsMatch(q[i], a[i] / b[i], exact)) << a[i] << " / " << b[i] << " = " << q[i];
      ASSERT_TRUE(test::floatsMatch(r[i], std::sqrt(a[i]), exact)) << "sqrt " << a[i] << " = " << r[i];
    }
  }
}

TEST(ClFpOptions, StatedToleranceAcceptsNearMissesOnly) {
  const test::Lists ref{{1, 2, 3}, {4}, {}, {5, 6}};
  test::Lists one_off = ref;
  one_off[1].push_back(7);
  EXPECT_TRUE(test::listsMatch(ref, ref, "list", true));
  EXPECT_FALSE(test::listsMatch(one_off, ref, "list", true));
  EXPECT_TRUE(test::listsMatch(one_off, ref, "list", false));
  test::Lists three_off = ref;
  three_off[0] = {1, 8, 9};  // 2 and 3 missing, 8 and 9 extra: 4 entries differ
  EXPECT_FALSE(test::listsMatch(three_off, ref, "list", false));
  test::Lists two_lists = one_off;
  two_lists[3] = {5};
  EXPECT_FALSE(test::listsMatch(two_lists, ref, "list", false)) << "2 of 4 lists differ: over 1% (min 1)";
  const std::vector<std::uint32_t> keys(5000, 3u);
  std::vector<std::uint32_t> near = keys;
  near[10] = near[20] = 4u;
  EXPECT_TRUE(test::valuesMatch(near, keys, "pixel", false));
  EXPECT_FALSE(test::valuesMatch(near, keys, "pixel", true));
  near[30] = near[40] = near[50] = near[60] = 4u;
  EXPECT_FALSE(test::valuesMatch(near, keys, "pixel", false));
  EXPECT_TRUE(test::floatsMatch(1.0f, std::nextafter(1.0f, 2.0f), false));
  EXPECT_FALSE(test::floatsMatch(1.0f, std::nextafter(1.0f, 2.0f), true));
  EXPECT_FALSE(test::floatsMatch(1.0f, 1.001f, false));
}

}  // namespace
}  // namespace ml
