// Pass times are never a made-up 0: a device whose profiling clock is unusable
// (Mesa rusticl reports the constants 0, 1, 2, 3) is timed on the host clock,
// marked as such; a device that gives an event no usable time leaves the pass
// missing (n/a in tables, null in JSON). Unit level on ClPassTimer and
// PassTimings with the test hook MANYLIGHTS_TEST_PROFILING, then the render
// table and --stats-json as a user sees them, then bench records.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/run/RunRecords.hpp"
#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "support/RunCommand.hpp"
#include "support/ScopedEnv.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

// A kernel that takes a measurable while: each item sums a long series.
const char* kBusySource = R"CL(
__kernel void busy(__global float* out, uint n) {
  float s = 0.0f;
  for (uint i = 0; i < n; ++i) s += native_sin((float)(i + get_global_id(0)));
  out[get_global_id(0)] = s;
}
)CL";

// Enqueues `passes` launches of busy through `timer` (pass names "busy-0", ...).
void runBusy(ClPassTimer& timer, int passes) {
  auto& rt = test::runtime();
  static const cl::Program program = rt.programs().buildSource("busy.cl", kBusySource);
  static cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, 1024 * sizeof(float));
  cl::Kernel k(program, "busy");
  k.setArg(0, out);
  k.setArg(1, cl_uint(20000));  // under llvmpipe's loop cap (tests/driver/driver_loop_cap_test.cpp)
  for (int i = 0; i < passes; ++i)
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1024), cl::NullRange, nullptr,
                                    timer.next("busy-" + std::to_string(i)));
}

bool onRusticl() { return test::runtime().info().platform_name.find("rusticl") != std::string::npos; }

TEST(PassTimings, MissingIsNaNNeverZeroAndHostClockIsKept) {
  PassTimings t;
  t.add("a", 1.5);
  t.add("b", 2.0, PassClock::Host);
  t.add("b", 0.5);  // part of a host-timed pass: still host
  t.addMissing("c");
  t.add("c", 3.0);  // missing plus anything stays missing
  EXPECT_EQ(t.clock("a"), PassClock::Device);
  EXPECT_EQ(t.clock("b"), PassClock::Host);
  EXPECT_DOUBLE_EQ(t.get("b"), 2.5);
  EXPECT_TRUE(PassTimings::isMissing(t.get("c")));
  EXPECT_TRUE(PassTimings::isMissing(t.total())) << "a total with a missing part is missing";
  EXPECT_TRUE(t.anyHost());
  EXPECT_TRUE(t.anyMissing());
  EXPECT_EQ(t.get("never-ran"), 0.0);
  EXPECT_EQ(passTimeText(t.get("c")), "n/a");
  EXPECT_EQ(passTimeText(1.25, 2), "1.25");
  PassTimings merged;
  merged.merge(t);
  EXPECT_EQ(merged.clock("b"), PassClock::Host);
  EXPECT_TRUE(PassTimings::isMissing(merged.get("c")));
}

// On every device at hand: no pass reads 0, and rusticl's passes are host-timed.
TEST(ClPassTimer, RealPassesHaveNonZeroTimesOnTheRightClock) {
  ClPassTimer timer;
  runBusy(timer, 3);
  PassTimings t;
  timer.collect(t);
  ASSERT_EQ(t.entries().size(), 3u);
  const bool device_clock = deviceProfilingWorks(test::runtime().context(), test::runtime().device());
  if (onRusticl()) {
    EXPECT_FALSE(device_clock) << "rusticl's profiling clock is constant";
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& [name, ms] = t.entries()[i];
    EXPECT_FALSE(PassTimings::isMissing(ms)) << name;
    EXPECT_GT(ms, 0.0) << name;
    EXPECT_EQ(t.clockAt(i), device_clock ? PassClock::Device : PassClock::Host) << name;
  }
  EXPECT_EQ(timer.usesHostClock(), !device_clock);
}

TEST(ClPassTimer, UnusableDeviceClockFallsBackToTheHostClock) {
  test::ScopedEnv hook("MANYLIGHTS_TEST_PROFILING", "host");
  ClPassTimer timer(test::runtime().queue());
  runBusy(timer, 2);
  PassTimings t;
  timer.collect(t);
  ASSERT_EQ(t.entries().size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(t.clockAt(i), PassClock::Host);
    EXPECT_GT(t.entries()[i].second, 0.0);
  }
}

TEST(ClPassTimer, EventsWithoutUsableTimesAreMissing) {
  test::ScopedEnv hook("MANYLIGHTS_TEST_PROFILING", "broken");
  if (!deviceProfilingWorks(test::runtime().context(), test::runtime().device())) {
    // A host-clock device never reads its events' times: the hook cannot break them.
    ClPassTimer timer;
    runBusy(timer, 1);
    PassTimings t;
    timer.collect(t);
    EXPECT_EQ(t.clock("busy-0"), PassClock::Host);
    EXPECT_GT(t.get("busy-0"), 0.0);
    return;
  }
  ClPassTimer timer;
  runBusy(timer, 2);
  PassTimings t;
  timer.collect(t);
  ASSERT_EQ(t.entries().size(), 2u);
  for (const auto& [name, ms] : t.entries()) EXPECT_TRUE(PassTimings::isMissing(ms)) << name << " = " << ms;
}

// ---- As a user sees them: the render table and --stats-json ----

constexpr const char* kRender = "render --size 48x32 --technique tiled-deferred --frames 1 --warmup 0 --lights 64";

TEST(ClPassTimer, RenderTableAndJsonMarkHostClockPasses) {
  const std::string json = test::tempDir() + "/host-clock.json";
  const auto r = test::runManylights(std::string(kRender) + " --stats-json " + json,
                                     "MANYLIGHTS_TEST_PROFILING=host MANYLIGHTS_GL_TIMING=host");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(host)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(" 0.000\n"), std::string::npos) << "a pass read 0: " << r.out;
  const auto j = test::readJson(json);
  ASSERT_FALSE(j["passes"].empty());
  for (const auto& [name, ms] : j["passes"].items()) {
    EXPECT_TRUE(ms.is_number()) << name;
    if (ms.is_number()) {
      EXPECT_GT(ms.get<double>(), 0.0) << name;
    }
    EXPECT_EQ(j["pass_clocks"][name], "host") << name;
  }
}

TEST(ClPassTimer, RenderTableAndJsonShowMissingTimes) {
  if (!deviceProfilingWorks(test::runtime().context(), test::runtime().device()))
    return;  // host-clock devices have no missing times (RealPassesHaveNonZeroTimesOnTheRightClock)
  const std::string json = test::tempDir() + "/missing.json";
  const auto r = test::runManylights(std::string(kRender) + " --stats-json " + json, "MANYLIGHTS_TEST_PROFILING=broken");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("n/a"), std::string::npos) << r.out;
  const auto j = test::readJson(json);
  int nulls = 0;
  for (const auto& [name, ms] : j["passes"].items()) {
    nulls += ms.is_null();
    if (ms.is_number()) {
      EXPECT_GT(ms.get<double>(), 0.0) << name << ": 0 where a time is missing";
    }
  }
  EXPECT_GT(nulls, 0) << j["passes"].dump();
}

// ---- Bench records: null, never 0; which clock ----

TEST(ClPassTimer, BenchRecordsCarryNullAndTheClockNeverZero) {
  FrameRecord r;
  r.run = "r";
  r.timed = true;
  r.passes.add("tile-cull", 1.0, PassClock::Host);
  r.passes.addMissing("tile-fill");
  r.passes_total_ms = r.passes.total();
  FrameRecord r2 = r;
  r2.passes = PassTimings();
  r2.passes.add("tile-cull", 3.0, PassClock::Host);
  r2.passes.add("tile-fill", 2.0);
  r2.passes_total_ms = r2.passes.total();
  const auto j = recordJson(r);
  EXPECT_EQ(j["passes"]["tile-cull"], 1.0);
  EXPECT_TRUE(j["passes"]["tile-fill"].is_null());
  EXPECT_TRUE(j["passes_total_ms"].is_null());
  EXPECT_EQ(j["pass_clocks"]["tile-cull"], "host");
  EXPECT_EQ(j["pass_clocks"]["tile-fill"], "device");
  const auto sums = summarizeRuns({r, r2});
  ASSERT_EQ(sums.size(), 1u);
  const auto s = summaryJson(sums[0]);
  EXPECT_EQ(s["passes"]["tile-fill"]["median"], 2.0) << "the missing frame does not count as 0";
  EXPECT_EQ(s["passes"]["tile-cull"]["median"], 2.0);
  EXPECT_EQ(s["pass_clocks"]["tile-cull"], "host");
  const std::string csv = benchCsv({r});
  EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
  EXPECT_EQ(csv.back(), '\n');
  EXPECT_EQ(csv.substr(csv.size() - 4), ",1,\n") << "tile-cull 1, then tile-fill empty: " << csv;
}

}  // namespace
}  // namespace ml
