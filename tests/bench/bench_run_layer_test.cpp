// The run layer's one median: `render` (timedRenders over --frames) and
// `bench` (timedRenders over --repeat) both reduce frames with medianOf(),
// which interpolates like summarize() (numpy's default). With an even count
// the upper median that `render` used to print differs, so this fails on it.
#include <gtest/gtest.h>

#include "host/run/RunLayer.hpp"

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

// A pass that ran on some frames only (a reused VCT volume, the hashed
// technique's skipped update): 0 ms on the others, whichever frame ran it
// (one that ran on a later frame only was once dropped), listed in the order
// passes first appear.
TEST(RunLayer, APassThatSkippedFramesCountsZeroThere) {
  std::vector<FrameResult> frames(3);
  frames[0].passes.add("vct-inject", 9.0);
  for (auto& f : frames) f.passes.add("vct-trace", 2.0);
  frames[2].passes.add("vct-mips", 4.0);
  frames[1].passes.add("vct-mips", 6.0);
  const TimedFrame t = medianOf(frames);
  ASSERT_EQ(t.passes.entries().size(), 3u);
  EXPECT_EQ(t.passes.entries()[0].first, "vct-inject");
  EXPECT_EQ(t.passes.entries()[1].first, "vct-trace");
  EXPECT_EQ(t.passes.entries()[2].first, "vct-mips");
  EXPECT_DOUBLE_EQ(t.passes.get("vct-inject"), 0.0);  // median of 9, 0, 0
  EXPECT_DOUBLE_EQ(t.passes.get("vct-trace"), 2.0);
  EXPECT_DOUBLE_EQ(t.passes.get("vct-mips"), 4.0);  // median of 0, 6, 4
  frames.pop_back();
  EXPECT_DOUBLE_EQ(medianOf(frames).passes.get("vct-inject"), 4.5);  // of two frames: interpolated
}

}  // namespace
}  // namespace ml
