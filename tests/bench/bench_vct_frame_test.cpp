// `manylights-vct-bench --frame` and scripts/plot_vct.py as a researcher runs
// them: a smallest sweep (16^3, 1 and 2 cones, 100 generated lights, one
// timed frame, which updates the volume as moving lights do) gives one record
// per case with every VCT pass timed, a finite
// error and the memory the grid settings imply; bad --frame flags are one line
// and exit 2; plot_vct.py turns the JSON into the plot and the Pareto table,
// and refuses a record lacking a field in one line.
#include "ml_bench_paths.h"  // MANYLIGHTS_VCT_BENCH (generated, when the bench is built)
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)
#include <gtest/gtest.h>

#ifdef MANYLIGHTS_VCT_BENCH

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "host/app/BenchCommand.hpp"
#include "host/vct/VoxelGrid.hpp"
#include "support/RunCommand.hpp"

namespace ml {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::lines;
using test::runShell;

constexpr unsigned kEdge = 16, kLevels = 4, kLights = 100;
const std::vector<unsigned> kCones{1, 2};
// Every frame's passes (plot_vct.py's time axis) and the first frame's voxelization.
constexpr const char* kFramePasses[] = {"vct-lists", "vct-inject", "vct-mips", "vct-textures", "vct-trace", "vct-upsample"};

CommandResult runVctBench(const std::string& args) { return runShell(std::string(MANYLIGHTS_VCT_BENCH) + " " + args); }

// The smallest useful sweep, run once per test process: its result and JSON path.
struct Sweep {
  CommandResult run;
  std::string json;
};
const Sweep& sweep() {
  static const Sweep s = [] {
    const std::string json = test::tempDir() + "/vct-frame.json";
    return Sweep{runVctBench("--frame --edges " + std::to_string(kEdge) + " --levels " + std::to_string(kLevels) +
                             " --cones 1,2 --frame-lights " + std::to_string(kLights) + " --reps 1 --json " + json),
                 json};
  }();
  return s;
}

TEST(BenchVctFrame, OneRecordPerCaseWithPassesErrorAndMemory) {
  const Sweep& s = sweep();
  ASSERT_EQ(s.run.exit_code, 0) << s.run.err << s.run.out;
  const auto j = test::readJson(s.json);
  ASSERT_TRUE(j.is_array());
  // scene x light count x voxels x iso/aniso x cones, each exactly once.
  std::set<std::tuple<std::string, unsigned, bool, unsigned>> cases;
  for (const auto& r : j) {
    SCOPED_TRACE(r.dump());
    cases.emplace(r.at("scene").get<std::string>(), r.at("voxels").get<unsigned>(), r.at("anisotropic").get<bool>(),
                  r.at("cones").get<unsigned>());
    EXPECT_EQ(r.at("lights").get<unsigned>(), kLights);
    EXPECT_EQ(r.at("levels").get<unsigned>(), kLevels);
    EXPECT_GE(r.at("vct-voxelize").get<double>(), 0.0);
    for (const char* p : kFramePasses) EXPECT_GE(r.at(p).get<double>(), 0.0) << p;
    // The timed frame updated the volume (the sweep sets the lights again:
    // static lights would reuse the first frame's and time 0 ms of inject).
    EXPECT_EQ(r.at("vct_updates").get<unsigned>(), 2u) << "the first frame and the one timed frame";
    for (const char* p : {"vct-inject", "vct-textures", "vct-trace"}) EXPECT_GT(r.at(p).get<double>(), 0.0) << p;
    const double e = r.at("gi_rel_rmse").get<double>();
    EXPECT_TRUE(std::isfinite(e) && e > 0) << e;
    // The error without the reference's own noise: below the raw one, and
    // the two tied by e^2 = corrected^2 + noise^2 (compareWithReference).
    const double noise = r.at("gi_ref_noise").get<double>(), corrected = r.at("gi_rel_rmse_corrected").get<double>();
    EXPECT_GT(noise, 0.0);
    EXPECT_LT(corrected, e);
    EXPECT_NEAR(corrected * corrected + noise * noise, e * e, 1e-6 * e * e + 1e-12);
    const vct::VoxelGridSettings g{r.at("voxels").get<unsigned>(), kLevels, r.at("anisotropic").get<bool>()};
    EXPECT_EQ(r.at("voxel_bytes").get<std::size_t>(), vct::voxelBytes(g));
  }
  std::set<std::tuple<std::string, unsigned, bool, unsigned>> expected;
  for (const char* scene : {"cornell", "default"})
    for (bool aniso : {false, true})
      for (unsigned c : kCones) expected.emplace(scene, kEdge, aniso, c);
  EXPECT_EQ(j.size(), expected.size());
  EXPECT_EQ(cases, expected);
  // The anisotropic volume adds the 6-direction levels: the two must differ.
  EXPECT_LT(vct::voxelBytes({kEdge, kLevels, false}), vct::voxelBytes({kEdge, kLevels, true}));
}

// A valid small --frame command line with `flag` set to `value` (each flag once: CLI11 refuses repeats).
std::string frameArgsWith(const std::string& flag, const std::string& value) {
  std::map<std::string, std::string> args{{"--reps", "1"}, {"--edges", "16"}, {"--cones", "1"}, {"--frame-lights", "100"}};
  args[flag] = value;
  std::string s = "--frame";
  for (const auto& [f, v] : args) s += " " + f + " " + v;
  return s;
}

TEST(BenchVctFrame, BadFrameFlagsAreOneLineAndExit2) {
  const struct {
    std::string flag, value;
  } cases[] = {
      {"--frame-lights", "0"}, {"--frame-lights", "10x"}, {"--frame-lights", ","},  {"--cones", "0"},
      {"--cones", "33"},       {"--cones", "1,x"},        {"--edges", "33"},        {"--edges", "0"},
      {"--edges", "1024"},     {"--levels", "6"},         {"--levels", "0"},        {"--frame-technique", "nope"},
      {"--reps", "0"},
  };
  for (const auto& c : cases) {
    const std::string args = frameArgsWith(c.flag, c.value);
    SCOPED_TRACE(args);
    const CommandResult r = runVctBench(args);
    EXPECT_EQ(r.exit_code, 2) << r.err << r.out;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << "expected '" << c.flag << "' in: " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
}

std::string plotPython() {
  const std::string python = findPlotPython();
  // CI installs it (scripts/packages.txt); without it plot_vct.py is untested, which must not pass.
  if (python.empty()) ADD_FAILURE() << "no python3 with matplotlib: install python3-matplotlib (or set MANYLIGHTS_PYTHON)";
  return python;
}

CommandResult runPlotVct(const std::string& python, const std::string& args) {
  return runShell(python + " " + MANYLIGHTS_SOURCE_DIR + "/scripts/plot_vct.py " + args);
}

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  std::string cell;
  std::getline(ss, cell, '|');  // before the first bar
  while (std::getline(ss, cell, '|')) {
    const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!out.empty() && out.back().empty()) out.pop_back();
  return out;
}

double frameMs(const nlohmann::json& r) {
  double ms = 0;
  for (const char* p : kFramePasses) ms += r.at(p).get<double>();
  return ms;
}

// A row of vct_pareto.md (| scene, N lights | 16^3 | iso | cones | ms | RMSE | MB |, the RMSE without the
// reference's noise) is this record's.
bool rowIsRecord(const std::vector<std::string>& c, const nlohmann::json& r) {
  const auto near = [](const std::string& printed, double v, double half_ulp) {
    return std::fabs(std::stod(printed) - v) <= half_ulp * 1.001;
  };
  return c[0] == r.at("scene").get<std::string>() + ", " + std::to_string(r.at("lights").get<unsigned>()) + " lights" &&
         c[1] == std::to_string(r.at("voxels").get<unsigned>()) + "^3" &&
         c[2] == (r.at("anisotropic").get<bool>() ? "aniso" : "iso") && c[3] == std::to_string(r.at("cones").get<unsigned>()) &&
         near(c[4], frameMs(r), 0.05) && near(c[5], r.at("gi_rel_rmse_corrected").get<double>(), 0.00005) &&
         near(c[6], r.at("voxel_bytes").get<double>() / 1e6, 0.05);
}

TEST(BenchVctFrame, PlotVctWritesThePlotAndAFrontOfRecords) {
  const Sweep& s = sweep();
  ASSERT_EQ(s.run.exit_code, 0) << s.run.err;
  const std::string python = plotPython();
  ASSERT_FALSE(python.empty());
  const std::string out = test::tempDir() + "/vct-plot";
  const CommandResult r = runPlotVct(python, s.json + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  ASSERT_TRUE(fs::is_regular_file(out + "/vct_error_vs_time.png"));
  EXPECT_GT(fs::file_size(out + "/vct_error_vs_time.png"), 0u);
  std::ifstream png(out + "/vct_error_vs_time.png", std::ios::binary);
  std::string magic(8, '\0');
  png.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");

  ASSERT_TRUE(fs::is_regular_file(out + "/vct_pareto.md"));
  EXPECT_GT(fs::file_size(out + "/vct_pareto.md"), 0u);
  const auto records = test::readJson(s.json);
  std::ifstream md(out + "/vct_pareto.md");
  std::string line;
  std::set<std::string> scenes;
  std::size_t rows = 0;
  for (int n = 0; std::getline(md, line); ++n) {
    if (n < 2) continue;  // header and alignment rows
    const auto c = cells(line);
    ASSERT_EQ(c.size(), 7u) << line;
    bool found = false;
    for (const auto& rec : records) found = found || rowIsRecord(c, rec);
    EXPECT_TRUE(found) << "a Pareto row that is no record: " << line;
    scenes.insert(c[0]);
    ++rows;
  }
  EXPECT_LE(rows, records.size());
  EXPECT_EQ(scenes, (std::set<std::string>{"cornell, 100 lights", "default, 100 lights"})) << "a front per panel";
}

TEST(BenchVctFrame, PlotVctRefusesARecordLackingAField) {
  const std::string python = plotPython();
  ASSERT_FALSE(python.empty());
  const std::string dir = test::tempDir() + "/vct-plot-bad";
  fs::create_directories(dir);
  nlohmann::json rec{{"scene", "cornell"}, {"voxels", 16},         {"anisotropic", false}, {"cones", 1},
                     {"vct-lists", 1.0},   {"vct-inject", 1.0},    {"vct-mips", 1.0},      {"vct-textures", 1.0},
                     {"vct-trace", 1.0},   {"vct-upsample", 1.0},  {"gi_rel_rmse", 0.5}};
  std::ofstream(dir + "/whole.json") << nlohmann::json::array({rec}).dump();
  const CommandResult whole = runPlotVct(python, dir + "/whole.json --out " + dir + "/whole");
  EXPECT_EQ(whole.exit_code, 0) << whole.err << "(the control: the same record with every field)";
  rec.erase("gi_rel_rmse");
  std::ofstream(dir + "/lacking.json") << nlohmann::json::array({rec}).dump();
  const CommandResult r = runPlotVct(python, dir + "/lacking.json --out " + dir + "/lacking");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("gi_rel_rmse"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("lacking.json"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/lacking/vct_pareto.md"));
}

}  // namespace
}  // namespace ml

#endif  // MANYLIGHTS_VCT_BENCH
