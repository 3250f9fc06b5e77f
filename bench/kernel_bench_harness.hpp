// The kernel bench's cases as Google Benchmark benchmarks (manual time):
//
//   Harness h(queue);
//   h.add(Case("scan.exclusive.u32", n, 8.0 * n).run(scan).checkedBy(compareWithTwin));
//   benchmark::RunSpecifiedBenchmarks();   // then h.failed()
//
// A case is registered as "<name>/<n>" (Google Benchmark appends
// "/manual_time"). Before its first timed run a case runs once untimed
// (kernel compiles, page faults) and `check` compares that run's output with
// its C++ twin: a case whose output differs reports Google Benchmark's
// error_occurred with the difference instead of a time, and failed() turns
// true. Each timed run calls `setup` first, outside the time.
//
// Timing. A device case is timed on the device's clock: a marker enqueued
// before the body and one after it, time = END(after) - END(before), which
// covers every command the body enqueued (blocking reads included) but not
// the host's wait for the queue to drain. Where the device's profiling clock
// is unusable (rusticl reports fixed fake times; some drivers fail or return
// zeros) or the span is longer than the host measured around it, that run is
// timed by the host clock around the same body and queue.finish(), and the
// case is labelled "timing=host"; device-clock cases are labelled
// "timing=events". Host cases (the std::sort and memcpy peers) are always
// "timing=host". Counters: bytes_per_second and items_per_second from the
// case's bytes and n over the manual time, plus the case's own `counters`.
#pragma once

#include <benchmark/benchmark.h>

#include <CL/opencl.hpp>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "host/cl/ClPassTimer.hpp"

namespace ml::kbench {

// One case, built fluently:
//   Case("radix_sort.u32", n, 8.0 * n).before(restore).run(sort).checkedBy(compare)
struct Case {
  Case(std::string case_name, std::size_t elements, double traffic)
      : name(std::move(case_name)), n(elements), bytes(traffic) {}
  Case& onHost() {
    device = false;
    return *this;
  }
  Case& before(std::function<void()> f) {
    setup = std::move(f);
    return *this;
  }
  Case& run(std::function<void()> f) {
    body = std::move(f);
    return *this;
  }
  Case& checkedBy(std::function<std::string()> f) {
    check = std::move(f);
    return *this;
  }
  Case& profiledBy(std::function<void(ClPassTimer&)> f) {
    profile = std::move(f);
    return *this;
  }
  Case& counter(const std::string& key, double value) {
    counters[key] = value;
    return *this;
  }

  std::string name;                    // "radix_sort.u32": the name the ratio script and the peers' tables use
  std::size_t n;                       // elements: items_per_second counts these
  double bytes;                        // the operation's minimum traffic (each element read and written once...)
  bool device = true;                  // false (onHost): runs on the host, no queue involved
  std::function<void()> setup;         // untimed, before every run (restores sort inputs)
  std::function<void()> body;          // the operation; device cases enqueue on the harness's queue
  std::function<std::string()> check;  // after one run: "" or what differs from the C++ twin
  // With --profile: one more untimed run with a pass timer; each pass becomes a
  // counter "pass:<name>_ms" (CL event times of that run).
  std::function<void(ClPassTimer&)> profile;
  std::map<std::string, double> counters;  // constant counters (e.g. passes)
};

// What a case's first (untimed) run found.
struct CaseStatus {
  bool done = false;
  std::string error;                      // from check(), or an exception's message
  std::map<std::string, double> pass_ms;  // --profile
};

class Harness {
 public:
  Harness(cl::CommandQueue& q, bool profile) : q_(q), profile_(profile) {}
  // Test hook (--check-self-test): for the case named `name`, the first run's
  // `setup` runs again between the body and the check, leaving the outputs as a
  // kernel that wrote nothing would (unsorted keys, poisoned buffers): its
  // check must then fail.
  void undoBeforeCheck(std::string name) { undo_ = std::move(name); }
  // Registers `c` with Google Benchmark (the harness must outlive the run).
  void add(Case c);
  bool failed() const { return failed_; }
  cl::CommandQueue& queue() { return q_; }

 private:
  void run(benchmark::State& state, const Case& c);
  void firstRun(const Case& c, CaseStatus& s);
  struct Sample {
    double seconds = 0;
    bool host_clock = false;
  };
  Sample timeOnce(const Case& c);

  cl::CommandQueue& q_;
  bool profile_;
  bool failed_ = false;
  std::string undo_;
  std::map<std::string, std::unique_ptr<Case>> cases_;
  std::map<std::string, CaseStatus> status_;
};

// One set of inputs alive at a time (a size's keys and buffers): get() with
// another key frees the previous set first, so that memory stays at one size's
// worth while the cases run in registration order.
class InputSlot {
 public:
  using Key = std::pair<int, std::size_t>;  // (kind of inputs, size): cheap inside timed bodies
  template <class T, class Make>
  T& get(Key key, Make&& make) {
    if (key != key_ || !obj_) {
      obj_.reset();
      std::unique_ptr<T> made = make();
      obj_ = std::shared_ptr<void>(std::move(made));
      key_ = key;
    }
    return *static_cast<T*>(obj_.get());
  }

 private:
  Key key_{-1, 0};
  std::shared_ptr<void> obj_;
};

}  // namespace ml::kbench
