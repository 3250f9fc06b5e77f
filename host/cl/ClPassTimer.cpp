#include "host/cl/ClPassTimer.hpp"

namespace ml {

void ClPassTimer::collect(PassTimings& out) {
  for (auto& [name, event] : events_) {
    if (!event()) continue;  // slot handed out but never enqueued
    event.wait();
    const cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    out.add(name, static_cast<double>(end - start) * 1e-6);
  }
  events_.clear();
}

}  // namespace ml
