#pragma once
// Host stage timers: milliseconds of the steady clock since a time point.
#include <chrono>

namespace ml {

using SteadyClock = std::chrono::steady_clock;

inline double msSince(SteadyClock::time_point t) {
  return std::chrono::duration<double, std::milli>(SteadyClock::now() - t).count();
}

}  // namespace ml
