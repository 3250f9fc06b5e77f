#pragma once
// Running `manylights view --script` under Xvfb for the viewer tests: writes
// the script, runs the binary through `xvfb-run -a` with the tests' small
// frame and light set, and compares PNGs as the render tests do.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "host/util/ImageIO.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_BINARY (generated)
#include "support/ImageCompare.hpp"
#include "support/RunCommand.hpp"

namespace ml::test {

inline constexpr const char* kViewFrame = "--size 160x96 --lights 48";

inline bool haveXvfb() { return runShell("command -v xvfb-run").exit_code == 0; }

// `view` with `actions` as its script, under a fresh Xvfb server.
inline CommandResult runViewScript(const nlohmann::json& actions, const std::string& name,
                                   const std::string& flags = "") {
  const std::string script = tempDir() + "/" + name + ".json", rc_file = tempDir() + "/" + name + ".rc";
  std::ofstream(script) << actions.dump(1);
  // ctest runs tests in parallel: each test process searches for a free X
  // server number from its own start (xvfb-run -a alone races to :99), and a
  // server that failed to start is tried once more.
  const std::string first_server = std::to_string(100 + ::getpid() % 20000);
  CommandResult r;
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::filesystem::remove(rc_file);
    // The viewer's own exit code goes through a file: xvfb-run replaces it
    // with its own when cleaning up its temporary folder fails.
    r = runShell("xvfb-run -a -n " + first_server + " -s '-screen 0 640x480x24' sh -c '" +
                 std::string(MANYLIGHTS_BINARY) + " view " + kViewFrame + " " + flags + " --script " + script +
                 "; echo $? >" + rc_file + "'");
    std::ifstream rc(rc_file);
    if (rc >> r.exit_code) return r;
  }
  r.exit_code = -1000 - r.exit_code;  // the viewer never ran (no X server) or never finished
  return r;
}

// Both PNGs exist, are the same size, and differ by no more than the render
// tests' tolerance (summation order only: mean < 1e-4, max channel 1/255 over
// at most 0.1% of the pixels, after 8-bit quantisation on both sides).
inline void expectSameImage(const std::string& a, const std::string& b) {
  ASSERT_TRUE(std::filesystem::exists(a)) << a;
  ASSERT_TRUE(std::filesystem::exists(b)) << b;
  unsigned wa = 0, ha = 0, wb = 0, hb = 0;
  const auto ia = readImageRgba(a, wa, ha), ib = readImageRgba(b, wb, hb);
  ASSERT_EQ(wa, wb) << a << " vs " << b;
  ASSERT_EQ(ha, hb) << a << " vs " << b;
  ASSERT_GT(luminanceStdDev(ia), 0.01) << a << ": a flat image proves nothing";
  const ImageDiff d = compareImages(ia, ib, 1.0 / 255.0 + 1e-6);
  EXPECT_LT(d.mean_abs, 1e-4) << a << " vs " << b << " max " << d.max_abs;
  EXPECT_LT(d.frac_over_tol, 1e-3) << a << " vs " << b << " max " << d.max_abs;
}

}  // namespace ml::test
