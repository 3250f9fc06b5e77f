// Helpers shared by the technique benchmarks (tiled, clustered, hashed):
// medians, repeated timing, JSON output and the error-reporting main().
// Comma lists use ml::splitList (host/run/SceneInputs.hpp), as the CLI does.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include "host/run/RunRecords.hpp"
#include "host/util/Error.hpp"

namespace ml::benchutil {

using Clock = std::chrono::steady_clock;

// The project's one median (ml::summarize, interpolated between order
// statistics, as `render` and `bench` report it); 0 for no samples.
inline double median(std::vector<double> v) { return summarize(std::move(v)).median; }

// One untimed warm-up call (kernel compile, buffer growth), then the median
// wall time of `reps` calls, in seconds.
template <class F>
double timeMedian(int reps, F&& f) {
  f();
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return median(t);
}

// Process CPU time (user + system, all threads: the OpenCL runtime's workers
// included), in seconds. On a shared machine it counts the work done rather
// than the time other processes took.
inline double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct WallCpu {
  double wall = 0, cpu = 0;  // medians, seconds
};

// timeMedian, also reporting the median process CPU time of the calls.
template <class F>
WallCpu timeMedianWallCpu(int reps, F&& f) {
  f();
  std::vector<double> w, c;
  for (int i = 0; i < reps; ++i) {
    const double c0 = cpuSeconds();
    const auto t0 = Clock::now();
    f();
    w.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    c.push_back(cpuSeconds() - c0);
  }
  return {median(w), median(c)};
}

// Fails before a long run, not after it, when `path` (given with `flag`)
// could not be written: its folder cannot be made (missing folders are
// created, as the manylights CLI does) or written in, or it is a folder.
// No-op when empty.
inline void requireWritable(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (fs::is_directory(p, ec)) throw UserError(flag + ": '" + path + "' is a directory");
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) throw UserError(flag + ": cannot create directory '" + dir.string() + "'");
  if (::access(dir.c_str(), W_OK) != 0) throw UserError(flag + ": cannot write in '" + dir.string() + "'");
}

// Writes `doc` to `path` (no-op when empty); UserError naming --json on failure.
template <class Json>
void writeJson(const std::string& path, const Json& doc) {
  if (path.empty()) return;
  std::ofstream out(path);
  if (!out) throw UserError("--json: cannot write '" + path + "'");
  out << doc.dump(2) << "\n";
  if (!out) throw UserError("--json: write to '" + path + "' failed");
  std::printf("\nwrote %s\n", path.c_str());
}

// Runs `run`, turning a UserError into one line on stderr and exit code 2.
template <class Run>
int benchMain(const char* program, Run&& run) {
  try {
    return run();
  } catch (const UserError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 2;
  }
}

}  // namespace ml::benchutil
