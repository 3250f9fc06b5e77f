// Render-target sizes (issue 18, item 4): a --size the GL driver or the
// memory budget cannot hold is a one-line UserError naming --size and the
// largest size of the same aspect ratio that passes, before anything is
// allocated (it was "framebuffer incomplete", exit 3, at 16384x16384).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "gl/RenderTargets.hpp"
#include "host/util/Error.hpp"
#include "support/RunCommand.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

std::string sizeError(unsigned w, unsigned h) {
  try {
    RenderTargets::checkSize(w, h);
  } catch (const UserError& e) {
    return e.what();
  }
  return {};
}

// "... the largest size of this aspect ratio is WxH ..." -> (W, H).
std::pair<unsigned, unsigned> largestNamed(const std::string& msg) {
  const std::string key = "the largest size of this aspect ratio is ";
  const auto at = msg.find(key);
  unsigned w = 0, h = 0;
  if (at != std::string::npos) std::sscanf(msg.c_str() + at + key.size(), "%ux%u", &w, &h);
  return {w, h};
}

// One more step of largestAtAspect's scale than (lw, lh) at the aspect of w x h.
std::pair<unsigned, unsigned> nextAtAspect(unsigned w, unsigned h, unsigned lw, unsigned lh) {
  const unsigned side = std::max(w, h), s = (w >= h ? lw : lh) + 1;
  return {std::max(1u, unsigned(std::uint64_t(w) * s / side)), std::max(1u, unsigned(std::uint64_t(h) * s / side))};
}

TEST(RenderTargetSize, TooLargeNamesSizeAndTheLargestThatPasses) {
  test::glContext();
  GLint max_tex = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
  const unsigned over = unsigned(max_tex) + 1;
  EXPECT_EQ(sizeError(320, 240), "");
  std::vector<std::pair<unsigned, unsigned>> cases = {{over, 16}, {16, over}, {over, over}};
  if (!sizeError(16384, 16384).empty()) cases.emplace_back(16384, 16384);  // llvmpipe: 4 GiB RGBA32F > 1 GiB
  for (const auto& [w, h] : cases) {
    const std::string msg = sizeError(w, h);
    SCOPED_TRACE(msg);
    ASSERT_NE(msg, "") << w << "x" << h << " passed";
    EXPECT_EQ(msg.rfind("--size " + std::to_string(w) + "x" + std::to_string(h) + ":", 0), 0u);
    EXPECT_EQ(msg.find('\n'), std::string::npos);
    const auto [lw, lh] = largestNamed(msg);
    ASSERT_GT(lw, 0u);
    ASSERT_GT(lh, 0u);
    EXPECT_LE(lw, w);
    EXPECT_LE(lh, h);
    // The named size passes; the next step at the same aspect does not.
    EXPECT_EQ(sizeError(lw, lh), "");
    const auto [nw, nh] = nextAtAspect(w, h, lw, lh);
    EXPECT_NE(sizeError(nw, nh), "") << nw << "x" << nh;
  }
}

TEST(RenderTargetSize, TheLargestSizeFitsTheBudgetAndNothingIsAllocatedFirst) {
  test::glContext();
  GLint max_tex = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
  const unsigned over = unsigned(max_tex) + 1;
  const auto [lw, lh] = largestNamed(sizeError(over, over));
  EXPECT_LE(std::size_t(lw) * lh * RenderTargets::kBytesPerPixel, RenderTargets::memoryBudget());
  EXPECT_THROW(RenderTargets(over, over), UserError);
}

TEST(RenderTargetSize, CliRefusesOversizedSizeWithOneLine) {
  test::glContext();
  if (sizeError(16384, 16384).empty()) GTEST_SKIP() << "this GL driver and memory hold 16384x16384 targets";
  const auto r = test::runManylights("render --technique forward --size 16384x16384");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--size 16384x16384"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("largest"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
}

}  // namespace
}  // namespace ml
