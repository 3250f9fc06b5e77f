// The run layer's one median: `render` (timedRenders over --frames) and
// `bench` (timedRenders over --repeat) both reduce frames with medianOf(),
// which interpolates like summarize() (numpy's default). With an even count
// the upper median that `render` used to print differs, so this fails on it.
#include <gtest/gtest.h>

#include "host/bench/RunLayer.hpp"

namespace ml {
namespace {

TEST(RunLayer, OneMedianForRenderAndBench) {
  const std::vector<double> host = {4.0, 1.0, 3.0, 2.0};
  std::vector<FrameResult> frames(host.size());
  for (std::size_t i = 0; i < host.size(); ++i) {
    frames[i].host_ms = host[i];
    frames[i].passes.add("assign", host[i]);
    frames[i].passes.add("shade", 10.0 * host[i]);
    frames[i].memory_bytes = 100 + i;
  }
  const TimedFrame t = medianOf(frames);
  EXPECT_DOUBLE_EQ(t.host_ms, 2.5);  // the upper median would be 3
  EXPECT_DOUBLE_EQ(t.host_ms, summarize(host).median);
  EXPECT_DOUBLE_EQ(t.passes.get("assign"), 2.5);
  EXPECT_DOUBLE_EQ(t.passes.get("shade"), 25.0);
  EXPECT_DOUBLE_EQ(t.passes_total_ms, 27.5);
  EXPECT_EQ(t.memory_bytes, 103u);  // the last render's
  // A bench record takes exactly these numbers.
  FrameRecord r;
  setTimes(r, t);
  EXPECT_TRUE(r.timed);
  EXPECT_DOUBLE_EQ(r.host_ms, t.host_ms);
  EXPECT_DOUBLE_EQ(r.passes_total_ms, t.passes_total_ms);
}

}  // namespace
}  // namespace ml
