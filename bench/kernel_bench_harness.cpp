// Google Benchmark registration, the untimed checked first run and the
// device-clock timing of the kernel bench (kernel_bench_harness.hpp).
#include "kernel_bench_harness.hpp"

#include <chrono>
#include <exception>

#include "host/cl/ClRuntime.hpp"
#include "host/util/PassTimings.hpp"

namespace ml::kbench {

using Clock = std::chrono::steady_clock;

void Harness::add(Case c) {
  const std::string full = c.name + "/" + std::to_string(c.n);
  auto owned = std::make_unique<Case>(std::move(c));
  const Case* ptr = owned.get();
  cases_[full] = std::move(owned);
  benchmark::RegisterBenchmark(full.c_str(), [this, ptr](benchmark::State& st) { run(st, *ptr); })
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
}

// The untimed first run: warm-up, then the comparison with the C++ twin, then
// (--profile) one run with per-pass event times.
void Harness::firstRun(const Case& c, CaseStatus& s) {
  s.done = true;
  try {
    if (c.setup) c.setup();
    c.body();
    if (c.device) q_.finish();
    if (c.setup && c.name == undo_) c.setup();
    if (c.check) s.error = c.check();
    if (s.error.empty() && profile_ && c.profile) {
      if (c.setup) c.setup();
      ClPassTimer timer;
      c.profile(timer);
      PassTimings t;
      timer.collect(t);
      for (const auto& [pass, ms] : t.entries()) s.pass_ms["pass:" + pass + "_ms"] += ms;
    }
  } catch (const cl::Error& e) {
    s.error = "OpenCL error: " + describeClError(e);
  } catch (const std::exception& e) {
    s.error = e.what();
  }
}

// One run of the body. Device cases: END(after) - END(before) of two markers,
// unless the device clock gave nothing usable (see the header).
Harness::Sample Harness::timeOnce(const Case& c) {
  const auto t0 = Clock::now();
  if (!c.device) {
    c.body();
    return {std::chrono::duration<double>(Clock::now() - t0).count(), true};
  }
  cl::Event before, after;
  q_.enqueueMarkerWithWaitList(nullptr, &before);
  c.body();
  q_.enqueueMarkerWithWaitList(nullptr, &after);
  q_.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  cl_ulong b = 0, a = 0;
  if (clGetEventProfilingInfo(before(), CL_PROFILING_COMMAND_END, sizeof b, &b, nullptr) != CL_SUCCESS ||
      clGetEventProfilingInfo(after(), CL_PROFILING_COMMAND_END, sizeof a, &a, nullptr) != CL_SUCCESS)
    return {wall, true};
  const double span = 1e-9 * double(a - b);
  // A span of 0 (fixed fake times), backwards, or longer than the host saw
  // around it (a clock that is not in nanoseconds) is not a measurement.
  if (b == 0 || a <= b || span > wall * 1.05 + 1e-5) return {wall, true};
  return {span, false};
}

void Harness::run(benchmark::State& state, const Case& c) {
  CaseStatus& s = status_[c.name + "/" + std::to_string(c.n)];
  if (!s.done) firstRun(c, s);
  if (!s.error.empty()) {
    failed_ = true;
    state.SkipWithError(s.error.c_str());
    return;
  }
  bool host_clock = !c.device;
  for (auto _ : state) {
    if (c.setup) c.setup();
    const Sample t = timeOnce(c);
    host_clock = host_clock || t.host_clock;
    state.SetIterationTime(t.seconds);
  }
  // Rates over the manual time (Google Benchmark divides kIsRate counters by it).
  const double runs = double(state.iterations());
  state.counters["bytes_per_second"] = benchmark::Counter(c.bytes * runs, benchmark::Counter::kIsRate);
  state.counters["items_per_second"] = benchmark::Counter(double(c.n) * runs, benchmark::Counter::kIsRate);
  for (const auto& [name, value] : c.counters) state.counters[name] = value;
  for (const auto& [name, ms] : s.pass_ms) state.counters[name] = ms;
  state.SetLabel(host_clock ? "timing=host" : "timing=events");
}

}  // namespace ml::kbench
