// manylights-kernel-bench and scripts/kernel_bench_ratios.py as their users
// run them: a tiny run of every case (odd size 4099, so the copy kernel's tail
// runs, the 1080p cases, a 16^3 mip volume; 2 repetitions of 0.01 s) writes
// Google Benchmark's JSON, every case has a non-zero time, its counters and
// the clock that timed it (device cases on PoCL: its events); the ratio script's figures (fraction of the copy
// bound, radix bandwidth bound, speed-ups over the peers) equal what this
// test recomputes from the raw JSON; its compare mode reads two files; a case
// whose output is undone before its check (as a kernel that writes nothing)
// reports an error instead of a time and fails the run; bad flags are one line.
#include <gtest/gtest.h>

#include "ml_bench_paths.h"  // MANYLIGHTS_KERNEL_BENCH (generated, when the bench is built)
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)

#ifdef MANYLIGHTS_KERNEL_BENCH

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "support/RunCommand.hpp"

namespace ml {
namespace {

using test::CommandResult;
using test::lines;
using test::runShell;

constexpr std::size_t kN = 4099, kFrame = 1920 * 1080, kVoxels = 16 * 16 * 16, kTileLights = 2000;
const std::vector<std::string> kSizeCases = {
    "copy.host_memcpy",     "copy.host_memcpy_par", "copy.cl_enqueue_copy", "copy.cl_kernel_uint4",   "radix_sort.u32",
    "radix_sort.u32_pairs", "radix_sort.u64",       "bitonic_sort.u32",     "boost_compute_sort.u32", "std_sort.u32",
    "std_sort_par.u32",     "scan.exclusive.u32",   "reduce.sum.u32",       "compact.half.u32"};
const std::vector<std::string> kFrameCases = {"scan.exclusive.u32.1080p", "segmented_sort.pairs.seg256.1080p",
                                              "segmented_sort.pairs.var256.1080p", "tile_minmax.depth16.1080p"};
const std::vector<std::string> kTileCases = {"tile_cull.minmax.1080p", "tile_cull_pair_atomics.minmax.1080p",
                                             "tile_cull_cpp_tbb.minmax.1080p"};
const std::set<std::string> kHostCases = {"copy.host_memcpy", "copy.host_memcpy_par", "std_sort.u32",
                                          "std_sort_par.u32", "tile_cull_cpp_tbb.minmax.1080p"};

CommandResult runBench(const std::string& args) { return runShell(std::string(MANYLIGHTS_KERNEL_BENCH) + " " + args); }
CommandResult runRatios(const std::string& args) {
  return runShell("python3 " + std::string(MANYLIGHTS_SOURCE_DIR) + "/scripts/kernel_bench_ratios.py " + args);
}

struct TinyRun {
  CommandResult run;
  std::string json;
};
const TinyRun& tinyRun() {
  static const TinyRun r = [] {
    const std::string json = test::tempDir() + "/kernel-bench.json";
    return TinyRun{runBench("--sizes " + std::to_string(kN) +
                        " --mips-edges 16 --mips-levels 3 --tile-lights " + std::to_string(kTileLights) + " --reps 2 --benchmark_min_time=0.01 --json " + json),
               json};
  }();
  return r;
}

// The iteration rows of a case, by "<case>/<n>".
std::map<std::string, std::vector<nlohmann::json>> iterationRows(const nlohmann::json& doc) {
  std::map<std::string, std::vector<nlohmann::json>> rows;
  for (const auto& b : doc.at("benchmarks"))
    if (b.at("run_type") == "iteration") rows[b.at("run_name").get<std::string>()].push_back(b);
  return rows;
}

// The median aggregate's field of `run_name`.
double median(const nlohmann::json& doc, const std::string& run_name, const std::string& field) {
  for (const auto& b : doc.at("benchmarks"))
    if (b.at("run_name") == run_name && b.at("run_type") == "aggregate" && b.at("aggregate_name") == "median")
      return b.at(field).get<double>();
  ADD_FAILURE() << "no median aggregate for " << run_name;
  return NAN;
}

std::string caseName(const std::string& c, std::size_t n) { return c + "/" + std::to_string(n) + "/manual_time"; }

TEST(BenchKernel, GoogleBenchmarkJsonWithATimeForEveryCase) {
  const TinyRun& r = tinyRun();
  ASSERT_EQ(r.run.exit_code, 0) << r.run.err << r.run.out;
  const auto doc = test::readJson(r.json);
  ASSERT_TRUE(doc.at("context").is_object());
  for (const char* k : {"date", "host_name", "executable", "num_cpus", "library_build_type", "device", "tuning"})
    EXPECT_TRUE(doc.at("context").contains(k)) << k;
  std::set<std::string> want;
  for (const auto& c : kSizeCases) want.insert(caseName(c, kN));
  for (const auto& c : kFrameCases) want.insert(caseName(c, kFrame));
  for (const char* c : {"vct_mips.isotropic", "vct_mips.anisotropic"}) want.insert(caseName(c, kVoxels));
  for (const auto& c : kTileCases) want.insert(caseName(c, kTileLights));
  // PoCL's profiling clock works: its device cases must be timed by events
  // (a marker-span check that always fell back to the host clock fails here).
  const bool profiling_device =
      doc.at("context").at("device").get<std::string>().find("Portable Computing Language") != std::string::npos;
  const auto rows = iterationRows(doc);
  std::set<std::string> got;
  for (const auto& row : rows) {
    const std::string& name = row.first;  // named references: clang 14 cannot capture a structured binding
    const auto& reps = row.second;
    got.insert(name);
    SCOPED_TRACE(name);
    EXPECT_EQ(reps.size(), 2u) << "--reps 2";
    for (const auto& b : reps) {
      EXPECT_FALSE(b.value("error_occurred", false)) << b.value("error_message", "");
      for (const char* k : {"name", "family_index", "per_family_instance_index", "repetitions", "repetition_index",
                            "threads", "iterations", "real_time", "cpu_time", "time_unit", "label"})
        EXPECT_TRUE(b.contains(k)) << k;
      EXPECT_GT(b.at("iterations").get<std::int64_t>(), 0);
      EXPECT_GT(b.at("real_time").get<double>(), 0.0);
      EXPECT_EQ(b.at("time_unit"), "us");
      EXPECT_GT(b.at("bytes_per_second").get<double>(), 0.0);
      EXPECT_GT(b.at("items_per_second").get<double>(), 0.0);
      const std::string label = b.at("label");
      const std::string base = name.substr(0, name.find('/'));
      if (kHostCases.count(base))
        EXPECT_EQ(label, "timing=host");
      else if (profiling_device)
        EXPECT_EQ(label, "timing=events");
      else
        EXPECT_TRUE(label == "timing=events" || label == "timing=host") << label;
    }
    for (const char* agg : {"mean", "median", "stddev"}) {
      const bool found = std::any_of(doc.at("benchmarks").begin(), doc.at("benchmarks").end(), [&](const auto& b) {
        return b.at("run_name") == name && b.at("run_type") == "aggregate" && b.at("aggregate_name") == agg;
      });
      EXPECT_TRUE(found) << agg;
    }
  }
  EXPECT_EQ(got, want);
  EXPECT_GE(median(doc, caseName("radix_sort.u32", kN), "passes"), 1.0);
}

double fastestCopy(const nlohmann::json& doc, const std::vector<std::string>& copies, double& seconds) {
  double best = 0;
  for (const auto& c : copies) {
    const double bps = median(doc, caseName(c, kN), "bytes_per_second");
    if (bps > best) {
      best = bps;
      seconds = median(doc, caseName(c, kN), "real_time") * 1e-6;
    }
  }
  return best;
}

TEST(BenchKernel, RatioScriptComputesItsFiguresFromTheJson) {
  const TinyRun& r = tinyRun();
  ASSERT_EQ(r.run.exit_code, 0) << r.run.err;
  const auto doc = test::readJson(r.json);
  const std::string figs = test::tempDir() + "/kernel-figures.json";
  const CommandResult s = runRatios(r.json + " --json " + figs);
  ASSERT_EQ(s.exit_code, 0) << s.err << s.out;
  EXPECT_NE(s.out.find("| n | ours | peer | speed-up |"), std::string::npos) << s.out;
  const auto f = test::readJson(figs);
  EXPECT_TRUE(f.at("failed").empty()) << f.at("failed").dump();

  const double radix = median(doc, caseName("radix_sort.u32", kN), "real_time");
  std::set<std::string> peers;
  for (const auto& sp : f.at("speedups")) {
    if (sp.at("case") != "radix_sort.u32") continue;
    const std::string peer = sp.at("peer");
    peers.insert(peer);
    EXPECT_NEAR(sp.at("speedup").get<double>(), median(doc, caseName(peer, kN), "real_time") / radix, 1e-9) << peer;
  }
  EXPECT_EQ(peers, (std::set<std::string>{"boost_compute_sort.u32", "std_sort.u32", "std_sort_par.u32"}));
  const double cull = median(doc, caseName(kTileCases[0], kTileLights), "real_time");
  std::set<std::string> cull_peers;
  for (const auto& sp : f.at("speedups")) {
    if (sp.at("case") != kTileCases[0]) continue;
    const std::string peer = sp.at("peer");
    cull_peers.insert(peer);
    EXPECT_NEAR(sp.at("speedup").get<double>(), median(doc, caseName(peer, kTileLights), "real_time") / cull, 1e-9);
  }
  EXPECT_EQ(cull_peers, (std::set<std::string>{kTileCases[1], kTileCases[2]}));

  double t_any = 0, t_device = 0;
  const double best = fastestCopy(
      doc, {"copy.host_memcpy", "copy.host_memcpy_par", "copy.cl_enqueue_copy", "copy.cl_kernel_uint4"}, t_any);
  bool scan_seen = false;
  for (const auto& c : f.at("copy_fraction"))
    if (c.at("case") == "scan.exclusive.u32" && c.at("n") == kN) {
      scan_seen = true;
      EXPECT_NEAR(c.at("fraction").get<double>(),
                  median(doc, caseName("scan.exclusive.u32", kN), "bytes_per_second") / best, 1e-9);
    }
  EXPECT_TRUE(scan_seen) << f.at("copy_fraction").dump();

  fastestCopy(doc, {"copy.cl_enqueue_copy", "copy.cl_kernel_uint4"}, t_device);
  bool four = false;
  for (const auto& b : f.at("radix_bound"))
    if (b.at("passes") == 4) {
      four = true;
      const double bound = kN / (4 * t_device);
      EXPECT_NEAR(b.at("fraction").get<double>(), (kN / (radix * 1e-6)) / bound, 1e-6);
    }
  EXPECT_TRUE(four) << f.at("radix_bound").dump();
}

TEST(BenchKernel, CompareModeReadsTwoRuns) {
  const TinyRun& r = tinyRun();
  ASSERT_EQ(r.run.exit_code, 0) << r.run.err;
  const CommandResult s = runRatios("--compare " + r.json + " " + r.json);
  ASSERT_EQ(s.exit_code, 0) << s.err << s.out;
  EXPECT_NE(s.out.find("| radix_sort.u32 | 4099 |"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("| 1.00 |"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("speed-up old"), std::string::npos) << s.out;
}

TEST(BenchKernel, OutputUndoneBeforeItsCheckReportsAnErrorNotATime) {
  for (const std::string c :
       {"radix_sort.u32", "scan.exclusive.u32", "reduce.sum.u32", "copy.cl_kernel_uint4", "tile_cull.minmax.1080p"}) {
    SCOPED_TRACE(c);
    const std::string json = test::tempDir() + "/undone-" + c + ".json";
    const CommandResult r = runBench("--sizes " + std::to_string(kN) + " --tile-lights " + std::to_string(kN) + " --mips-edges '' --filter " + c + "/" +
                                     " --benchmark_min_time=0.01 --check-self-test " + c + " --json " + json);
    EXPECT_EQ(r.exit_code, 1) << r.err << r.out;
    EXPECT_NE(r.err.find("differs from its C++ twin"), std::string::npos) << r.err;
    const auto doc = test::readJson(json);
    ASSERT_EQ(doc.at("benchmarks").size(), 1u) << doc.dump();
    const auto& b = doc.at("benchmarks")[0];
    EXPECT_TRUE(b.value("error_occurred", false));
    EXPECT_FALSE(b.value("error_message", "").empty());
    const CommandResult s = runRatios(json);
    EXPECT_EQ(s.exit_code, 0) << s.err;
    EXPECT_NE(s.out.find("FAILED " + c + "/4099"), std::string::npos) << s.out;
  }
}

TEST(BenchKernel, BadFlagsAreOneLineAndExitTwo) {
  for (const std::string args : {"--nope", "--benchmark_nope=1", "--sizes 0", "--sizes 12,x", "--mips-edges 12",
                                 "--shape wide", "--filter a --benchmark_filter=b", "--tile-lights 0", "--tile-lights x"}) {
    SCOPED_TRACE(args);
    const CommandResult r = runBench(args);
    EXPECT_EQ(r.exit_code, 2) << r.err << r.out;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
  const std::string bad = test::tempDir() + "/not-gbench.json";
  std::ofstream(bad) << R"({"records": []})";
  const CommandResult s = runRatios(bad);
  EXPECT_EQ(s.exit_code, 2) << s.err << s.out;
  EXPECT_EQ(lines(s.err), 1) << s.err;
  EXPECT_NE(s.err.find("not Google Benchmark JSON"), std::string::npos) << s.err;
}

}  // namespace
}  // namespace ml

#endif  // MANYLIGHTS_KERNEL_BENCH
