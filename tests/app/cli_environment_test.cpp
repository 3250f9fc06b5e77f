// Environment variables are checked at start-up: a bad MANYLIGHTS_GL_TIMING or
// MANYLIGHTS_SOURCE_DIR is one line naming the variable and exit 2, before any
// GL/CL start-up line; an unusable MANYLIGHTS_CACHE_DIR is one warning line
// and the run goes on uncached (the render side is in cl_program_cache_test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gl/GlPassTimer.hpp"
#include "host/util/EmbeddedFiles.hpp"
#include "host/util/Error.hpp"
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated): this checkout
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"

namespace ml {
namespace {

// Sets an environment variable for one scope, restoring the old value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

using test::lines;

// A render that must stop at the environment check: exit 2, one line on
// stderr containing every string of `expect`, nothing on stdout.
void expectRefused(const std::string& env, const std::vector<std::string>& expect) {
  const auto r = test::runManylights("render --size 64x48", env);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  for (const auto& e : expect) EXPECT_NE(r.err.find(e), std::string::npos) << "missing '" << e << "': " << r.err;
  EXPECT_EQ(r.out, "") << "no start-up line before the error";
}

TEST(CliEnvironment, BogusGlTimingIsRefused) {
  expectRefused("MANYLIGHTS_GL_TIMING=bogus", {"MANYLIGHTS_GL_TIMING", "query", "host", "bogus"});
  ScopedEnv env("MANYLIGHTS_GL_TIMING", "Host");
  EXPECT_THROW(glTimingModeFromEnv(), UserError);
}

// Used to say "no EGL display ... install libegl-mesa0", as if Mesa were missing.
TEST(CliEnvironment, BogusEglPlatformIsRefused) {
  expectRefused("MANYLIGHTS_EGL=bogus", {"MANYLIGHTS_EGL", "device", "surfaceless", "bogus"});
}

TEST(CliEnvironment, GlTimingValues) {
  {
    ScopedEnv env("MANYLIGHTS_GL_TIMING", "host");
    EXPECT_EQ(glTimingModeFromEnv(), GlTimingMode::Host);
  }
  {
    ScopedEnv env("MANYLIGHTS_GL_TIMING", "query");
    EXPECT_EQ(glTimingModeFromEnv(), GlTimingMode::Query);
  }
  ScopedEnv env("MANYLIGHTS_GL_TIMING", "");
  EXPECT_EQ(glTimingModeFromEnv(), GlTimingMode::Auto);
}

TEST(CliEnvironment, MissingSourceDirIsRefused) {
  test::TempDir tmp;
  const std::string missing = tmp.file("nope");
  expectRefused("MANYLIGHTS_SOURCE_DIR=" + missing, {"MANYLIGHTS_SOURCE_DIR", missing});
}

TEST(CliEnvironment, SourceDirThatIsNoSourceTreeIsRefused) {
  test::TempDir tmp;
  std::filesystem::create_directories(tmp.file("kernels"));  // but no gl/shaders/
  expectRefused("MANYLIGHTS_SOURCE_DIR=" + tmp.file(""), {"MANYLIGHTS_SOURCE_DIR", "gl/shaders"});
  const std::string file = tmp.write("a-file", "x");
  expectRefused("MANYLIGHTS_SOURCE_DIR=" + file, {"MANYLIGHTS_SOURCE_DIR", file});
}

TEST(CliEnvironment, SourceDirOfThisCheckoutIsAccepted) {
  ScopedEnv env("MANYLIGHTS_SOURCE_DIR", MANYLIGHTS_SOURCE_DIR);
  EXPECT_EQ(sourceDirFromEnv(), MANYLIGHTS_SOURCE_DIR);
  EXPECT_NE(readEmbeddedFile("kernels/compute/scan.cl").find("__kernel"), std::string::npos);
}

TEST(CliEnvironment, UnusableCacheDirWarnsBeforeStartupLines) {
  test::TempDir tmp;
  const std::string file = tmp.write("a-file", "x");
  // --frames 0 fails after the environment check but before GL/CL: the
  // warning must come first and alone.
  const auto r = test::runManylights("render --frames 0", "MANYLIGHTS_CACHE_DIR=" + file);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 2) << r.err;
  EXPECT_EQ(r.err.rfind("manylights: warning: kernel cache MANYLIGHTS_CACHE_DIR=" + file, 0), 0u) << r.err;
  EXPECT_NE(r.err.find("--frames"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ml
