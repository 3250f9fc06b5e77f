// `manylights-vct-bench --flight` as a researcher runs it: a smallest flight
// (the default scene's path resampled to 4 cameras, 16^3 voxels, 2 cascade
// levels, 2 cameras against the reference) writes one record per compared
// camera with a finite error for each configuration, and a summary with the
// cascade's memory and camera-move cost; bad --flight flags are one line and
// exit 2.
#include "ml_bench_paths.h"  // MANYLIGHTS_VCT_BENCH (generated, when the bench is built)
#include <gtest/gtest.h>

#ifdef MANYLIGHTS_VCT_BENCH

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "support/RunCommand.hpp"

namespace ml {
namespace {

using test::CommandResult;
using test::lines;
using test::runShell;

const char* const kConfigs[] = {"single 16", "cascade 2x16", "single 32"};

// The default scene unless `args` names the scenes.
CommandResult runFlight(const std::string& args) {
  std::string command = MANYLIGHTS_VCT_BENCH;
  command += " --flight ";
  if (args.find("--flight-scenes") == std::string::npos) command += "--flight-scenes default ";
  command += args;
  return runShell(command);
}

TEST(BenchVctFlight, RecordsPerCameraAndTheCascadesMoveCost) {
  const std::string json = test::tempDir() + "/vct-flight.json";
  const CommandResult r =
      runFlight("--flight-voxels 16 --flight-cascades 2 --flight-fold --flight-frames 4 --flight-samples 2 --json " +
                json);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = test::readJson(json);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 3u) << "2 compared cameras and a summary";
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(j[i].dump());
    EXPECT_EQ(j[i].at("camera").get<unsigned>(), i == 0 ? 0u : 3u) << "first and last camera";
    for (const char* c : kConfigs) {
      const double e = j[i].at(c).get<double>();
      EXPECT_TRUE(std::isfinite(e) && e > 0.0 && e < 2.0) << c;
    }
    const double fold = j[i].at("cascade 2x16 fold").get<double>();  // --flight-fold's column
    EXPECT_TRUE(std::isfinite(fold) && fold > 0.0 && fold < 2.0);
  }
  const auto& s = j[2];
  SCOPED_TRACE(s.dump());
  EXPECT_TRUE(s.at("summary").get<bool>());
  EXPECT_GT(s.at("cascade 2x16 voxel_bytes").get<double>(), s.at("single 16 voxel_bytes").get<double>());
  const auto& m = s.at("cascade_moves");
  EXPECT_GT(m.at("full_build_ms").get<double>(), 0.0);
  ASSERT_GE(m.at("moves").get<unsigned>(), 1u) << "a 31 m flight past 2 m voxels scrolled no level";
  EXPECT_GT(m.at("move_over_full_median").get<double>(), 0.0);
  EXPECT_GT(m.at("scrolled_voxels_mean").get<double>(), 0.0);
  EXPECT_LE(s.at("fold_lower_at").get<unsigned>(), 2u);
  EXPECT_GE(s.at("fold_moves").at("moves").get<unsigned>(), 1u);
}

TEST(BenchVctFlight, BadFlightFlagsAreOneLineAndExit2) {
  const struct {
    std::string flag, value;
  } cases[] = {
      {"--flight-frames", "1"},   {"--flight-samples", "0"}, {"--flight-cascades", "5"},
      {"--flight-cascades", "0"}, {"--flight-voxels", "33"}, {"--flight-scenes", "no-such-scene"},
      {"--flight-fold", "--flight-cascades 1"},
  };
  for (const auto& c : cases) {
    const std::string args = c.flag + " " + c.value;
    SCOPED_TRACE(args);
    const CommandResult r = runFlight(args);
    EXPECT_EQ(r.exit_code, 2) << r.err << r.out;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << "expected '" << c.flag << "' in: " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
}

}  // namespace
}  // namespace ml

#endif  // MANYLIGHTS_VCT_BENCH
