#pragma once
// Collects the CL events of named passes and turns them into device times
// (CL_PROFILING_COMMAND_START..END, so queueing delay is excluded). The queue
// must have CL_QUEUE_PROFILING_ENABLE (ClRuntime's has).
#include <CL/opencl.hpp>

#include <string>
#include <utility>
#include <deque>

#include "host/util/PassTimings.hpp"

namespace ml {

class ClPassTimer {
 public:
  // Returns an event slot to hand to enqueue*(…, &event) for pass `name`.
  cl::Event* next(const std::string& name) {
    events_.emplace_back(name, cl::Event());
    return &events_.back().second;
  }
  void record(const std::string& name, const cl::Event& e) { events_.emplace_back(name, e); }
  // Waits for all recorded events, adds their times to `out`, and clears.
  void collect(PassTimings& out);
  bool empty() const { return events_.empty(); }

 private:
  std::deque<std::pair<std::string, cl::Event>> events_;  // deque: next() pointers stay valid
};

}  // namespace ml
