// manylights-kernel-bench: the compute primitives against their peers, on the
// same device and the same inputs, in one run, as Google Benchmark cases.
//
//   manylights-kernel-bench [--sizes 65536,1048576,...] [--quick] [--device D] [--filter TEXT[,TEXT...]]
//                           [--reps N] [--json F] [--profile] [--shape auto|cpu|gpu] [--chunks N]
//                           [--radix-bits B] [--sort-chunk C] [--wg W] [--mips-edges E,...] [--mips-levels L]
//                           [--tile-lights N,...]
//                           [--benchmark_* flags of Google Benchmark]
//
// The cases and what each counts: kernel_bench_cases.hpp; timing, checks and
// labels: kernel_bench_harness.hpp. Our flags are parsed first; every
// --benchmark_* flag goes to Google Benchmark (--benchmark_filter,
// --benchmark_repetitions, --benchmark_out=F --benchmark_out_format=json|csv,
// --benchmark_min_time, ...). --json F is --benchmark_out=F in JSON, --reps N
// is --benchmark_repetitions=N, --filter a,b selects the cases whose name
// contains a or b. Unless given, --benchmark_min_time is 0.1 s per case, which
// keeps the default run at a few minutes on two cores; give 0.5 (Google
// Benchmark's default) or more, with repetitions, for figures to publish.
// scripts/kernel_bench_ratios.py derives the fraction of the copy bound and the
// speed-ups over the peers from the JSON, and compares two JSON files.
#include <benchmark/benchmark.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "BenchCommon.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/util/Error.hpp"
#include "kernel_bench_cases.hpp"

namespace {

using namespace ml;

constexpr const char* kProgram = "manylights-kernel-bench";

struct Args {
  std::string sizes_text = "65536,1048576,4194304,16777216";
  std::string json_path, device, filter, shape = "auto", mips_edges = "128", tile_lights = "10000,100000", self_test;
  unsigned mips_levels = 4;
  int reps = 0;
  bool quick = false, profile = false;
  compute::Options tune;
  std::vector<std::string> gbench;  // --benchmark_* flags, in order
};

void addOptions(CLI::App& app, Args& a) {
  app.add_option("--sizes", a.sizes_text, "comma-separated element counts (default 2^16,2^20,2^22,2^24)");
  app.add_flag("--quick", a.quick, "2^16 and 2^20 only, no 1080p cases, 0.05 s per case: a smoke run");
  app.add_option("--device", a.device, "OpenCL device: gpu, cpu, an index or a name such as pocl or rusticl (default as the app)");
  app.add_option("--filter", a.filter,
                 "run only the cases whose name contains this text (comma-separated: any of these)");
  app.add_option("--reps", a.reps, "repetitions (--benchmark_repetitions): mean, median, stddev and cv over them")
      ->check(CLI::PositiveNumber);
  app.add_option("--json", a.json_path, "write Google Benchmark's JSON to this file (--benchmark_out)");
  app.add_flag("--profile", a.profile, "per-pass CL event times of one extra run as counters pass:<name>_ms");
  app.add_option("--shape", a.shape, "kernel shape: auto, cpu (chunked work-items) or gpu (work-groups)")
      ->check(CLI::IsMember({"auto", "cpu", "gpu"}));
  app.add_option("--chunks", a.tune.chunks, "tuning override: CPU-shape work-items per launch");
  app.add_option("--radix-bits", a.tune.radix_bits, "tuning override: radix digit width")->check(CLI::Range(1u, 12u));
  app.add_option("--sort-chunk", a.tune.sort_chunk, "tuning override: CPU-shape bitonic block (power of two)");
  app.add_option("--wg", a.tune.work_group_size, "tuning override: GPU-shape work-group size (power of two)");
  app.add_option("--mips-edges", a.mips_edges, "VCT mip cases: grid edges, powers of two (default 128; '' for none)");
  app.add_option("--tile-lights", a.tile_lights,
                 "tile culling cases at 1080p: light counts (default 10000,100000; '' for none; --quick: none)");
  app.add_option("--mips-levels", a.mips_levels, "VCT mip cases: levels (default 4)")->check(CLI::Range(2u, 8u));
  app.add_option("--check-self-test", a.self_test,
                 "test hook: undo this case's output before its check, which must then fail")
      ->group("");
  app.footer(
      "Google Benchmark's flags pass through: --benchmark_filter=REGEX, --benchmark_repetitions=N,\n"
      "--benchmark_out=F --benchmark_out_format=json|csv, --benchmark_min_time=S (default here 0.1),\n"
      "--benchmark_report_aggregates_only=true, --benchmark_list_tests=true, ...\n"
      "Derived figures and comparisons: scripts/kernel_bench_ratios.py");
}

// "a,b,..." of counts in 1 .. 2^32-1; `flag` names the list in errors.
std::vector<std::size_t> parseCounts(const std::string& text, const std::string& flag) {
  std::vector<std::size_t> counts;
  for (const auto& item : splitList(text)) {
    const bool digits = !item.empty() && item.size() <= 12 && item.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoull(item) == 0 || std::stoull(item) >= (1ull << 32))
      throw UserError(flag + ": '" + item + "' is not a count in 1 .. 2^32-1");
    counts.push_back(std::stoull(item));
  }
  return counts;
}

std::vector<std::size_t> parseSizes(const Args& a) {
  if (a.quick) return {1u << 16, 1u << 20};
  std::vector<std::size_t> sizes = parseCounts(a.sizes_text, "--sizes");
  if (sizes.empty()) throw UserError("--sizes: no sizes given");
  return sizes;
}

std::vector<unsigned> parseEdges(const Args& a) {
  std::vector<unsigned> edges;
  for (const auto& item : splitList(a.mips_edges)) {
    const bool digits = !item.empty() && item.size() <= 4 && item.find_first_not_of("0123456789") == std::string::npos;
    const unsigned e = digits ? unsigned(std::stoul(item)) : 0;
    if (e < 2 || (e & (e - 1)) || e > 512 || (e >> (a.mips_levels - 1)) == 0)
      throw UserError("--mips-edges: '" + item + "' is not a power of two in 2 .. 512 with " +
                      std::to_string(a.mips_levels) + " levels");
    edges.push_back(e);
  }
  return edges;
}

// --filter a,b -> the regular expression "a|b" with each part taken literally.
std::string filterRegex(const std::string& filter) {
  std::string re;
  for (const auto& part : splitList(filter)) {
    if (part.empty()) continue;
    if (!re.empty()) re += '|';
    for (char c : part) {
      if (std::string("\\^$.|?*+()[]{}").find(c) != std::string::npos) re += '\\';
      re += c;
    }
  }
  return re;
}

bool gbenchFlagGiven(const Args& a, const std::string& name) {
  for (const auto& f : a.gbench)
    if (f.rfind("--" + name + "=", 0) == 0 || f == "--" + name) return true;
  return false;
}

// Our flags become Google Benchmark's: defaults first, so that flags given later win.
std::vector<std::string> gbenchArgs(const Args& a) {
  std::vector<std::string> out;
  if (!gbenchFlagGiven(a, "benchmark_min_time"))
    out.push_back(a.quick ? "--benchmark_min_time=0.05" : "--benchmark_min_time=0.1");
  if (!a.filter.empty()) {
    if (gbenchFlagGiven(a, "benchmark_filter")) throw UserError("--filter: give either --filter or --benchmark_filter");
    out.push_back("--benchmark_filter=" + filterRegex(a.filter));
  }
  if (a.reps) out.push_back("--benchmark_repetitions=" + std::to_string(a.reps));
  if (!a.json_path.empty()) {
    if (gbenchFlagGiven(a, "benchmark_out")) throw UserError("--json: give either --json or --benchmark_out");
    out.push_back("--benchmark_out=" + a.json_path);
    out.push_back("--benchmark_out_format=json");
  }
  out.insert(out.end(), a.gbench.begin(), a.gbench.end());
  return out;
}

// Splits argv: --benchmark_* to Google Benchmark, the rest to CLI11. Returns
// the exit code when the program stops here (help, a bad flag).
std::optional<int> parseArgs(CLI::App& app, Args& a, int argc, char** argv) {
  std::vector<std::string> ours;
  for (int i = argc - 1; i >= 1; --i) {
    const std::string arg = argv[i];
    (arg.rfind("--benchmark_", 0) == 0 ? a.gbench : ours).push_back(arg);
  }
  std::reverse(a.gbench.begin(), a.gbench.end());
  try {
    app.parse(ours);  // CLI11 takes the vector reversed
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 2;
  }
  return std::nullopt;
}

std::string tuningText(const kbench::Bench& b) {
  const compute::Tuning& t = b.radix.tuning();
  char line[200];
  std::snprintf(line, sizeof line, "shape %s, radix digit %u bits, %zu chunks, work-group %zu, bitonic block %zu",
                compute::shapeName(t.shape), t.radix_bits, t.chunks, t.wg, b.bitonic.blockSize());
  return line;
}

int runBenchmarks(Args& a) {
  a.tune.shape = a.shape == "cpu"   ? compute::Shape::CpuChunked
                 : a.shape == "gpu" ? compute::Shape::GpuWorkGroup
                                    : compute::Shape::Auto;
  const std::vector<std::size_t> sizes = parseSizes(a);
  const std::vector<unsigned> edges = parseEdges(a);
  const std::vector<std::size_t> tile_lights = a.quick ? std::vector<std::size_t>{} : parseCounts(a.tile_lights, "--tile-lights");
  benchutil::requireWritable("--json", a.json_path);
  std::vector<std::string> gb = gbenchArgs(a);
  std::vector<char*> gargv{const_cast<char*>(kProgram)};
  for (auto& s : gb) gargv.push_back(s.data());
  int gargc = int(gargv.size());
  benchmark::Initialize(&gargc, gargv.data());
  if (gargc > 1) throw UserError(std::string(gargv[1]) + ": not a flag of this bench or of Google Benchmark");

  auto rt = ClRuntime::create(DeviceChoice::resolve(a.device));
  kbench::Harness harness(rt->queue(), a.profile);
  harness.undoBeforeCheck(a.self_test);
  kbench::Bench bench(*rt, harness, a.tune);
  benchmark::AddCustomContext("device", rt->describe());
  benchmark::AddCustomContext("tuning", tuningText(bench));
  benchmark::AddCustomContext("host_threads", std::to_string(std::thread::hardware_concurrency()));
  for (const std::size_t n : sizes) kbench::addSizeCases(bench, n);
  if (!a.quick) kbench::add1080pCases(bench);
  for (const std::size_t n : tile_lights) kbench::addTileCullCases(bench, n);
  for (const unsigned e : edges) kbench::addVctCases(bench, e, a.mips_levels);

  const std::size_t ran = benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (ran == 0) throw UserError("no case matches the filter (list them with --benchmark_list_tests=true)");
  if (harness.failed()) {
    std::fprintf(stderr, "%s: error: a case's output differs from its C++ twin (error_message in the report)\n",
                 kProgram);
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "manylights kernel microbenchmarks (Google Benchmark): compute primitives vs Boost.Compute, "
      "std::sort and copies");
  Args a;
  addOptions(app, a);
  if (auto code = parseArgs(app, a, argc, argv)) return *code;
  return benchutil::benchMain(kProgram, [&] {
    try {
      return runBenchmarks(a);
    } catch (const cl::Error& e) {
      std::fprintf(stderr, "%s: OpenCL error: %s\n", kProgram, describeClError(e).c_str());
      return 1;
    }
  });
}
