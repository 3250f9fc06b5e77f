#include "host/cl/ClPassTimer.hpp"

#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string_view>
#include <thread>

namespace ml {

namespace {

std::string_view profilingHook() {
  const char* v = std::getenv("MANYLIGHTS_TEST_PROFILING");
  return v ? std::string_view(v) : std::string_view();
}

double hostNowMs() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

// START and END of a completed event; false on any error (raw calls: the
// wrapper would throw, and a device without times is not an error for us).
bool profilingTimes(const cl::Event& e, cl_ulong& start, cl_ulong& end) {
  return clGetEventProfilingInfo(e(), CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr) == CL_SUCCESS &&
         clGetEventProfilingInfo(e(), CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr) == CL_SUCCESS;
}

// Two small fills 3 ms apart on the host must be at least 1 ms apart on the
// device clock: a clock that does not advance, or returns constants, fails.
bool probeProfilingClock(const cl::Context& context, const cl::Device& device) {
  try {
    cl::CommandQueue q(context, device, CL_QUEUE_PROFILING_ENABLE);
    constexpr std::size_t kBytes = 1 << 16;
    cl::Buffer b(context, CL_MEM_READ_WRITE, kBytes);
    const cl_uint zero = 0;
    cl::Event first, second;
    q.enqueueFillBuffer(b, zero, 0, kBytes, nullptr, &first);
    first.wait();
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
    q.enqueueFillBuffer(b, zero, 0, kBytes, nullptr, &second);
    second.wait();
    cl_ulong s1 = 0, e1 = 0, s2 = 0, e2 = 0;
    if (!profilingTimes(first, s1, e1) || !profilingTimes(second, s2, e2)) return false;
    return s1 != 0 && e1 >= s1 && e2 >= s2 && s2 >= e1 + 1'000'000;
  } catch (const cl::Error&) {
    return false;
  }
}

}  // namespace

bool deviceProfilingWorks(const cl::Context& context, const cl::Device& device) {
  if (profilingHook() == "host") return false;
  static std::mutex mutex;
  static std::map<cl_device_id, bool> known;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = known.find(device());
  if (it != known.end()) return it->second;
  const bool works = probeProfilingClock(context, device);
  known.emplace(device(), works);
  return works;
}

void ClPassTimer::learnQueue(const cl::CommandQueue& queue) {
  queue_ = queue;
  mode_ = deviceProfilingWorks(queue.getInfo<CL_QUEUE_CONTEXT>(), queue.getInfo<CL_QUEUE_DEVICE>()) ? Mode::Device
                                                                                                    : Mode::Host;
}

ClPassTimer::Slot ClPassTimer::next(const std::string& name) {
  if (mode_ == Mode::Host) {
    settleAll();
    queue_.finish();  // the pass starts on an idle queue: earlier work is not its time
  }
  passes_.push_back({name, cl::Event(), hostNowMs()});
  return Slot(this, passes_.size() - 1);
}

void ClPassTimer::record(const std::string& name, const cl::Event& e) {
  passes_.push_back({name, e, hostNowMs()});
  passes_.back().bracketed = false;
}

void ClPassTimer::enqueued(std::size_t index) noexcept {
  if (index >= passes_.size()) return;
  Pass& p = passes_[index];
  if (!p.event()) return;  // converted but not (yet) enqueued: settled later
  try {
    if (mode_ == Mode::Unknown) learnQueue(p.event.getInfo<CL_EVENT_COMMAND_QUEUE>());
    if (mode_ == Mode::Host) settle(p);
  } catch (const cl::Error&) {
    // A destructor must not throw: collect() waits for the pass again and reports the error.
  }
}

void ClPassTimer::settle(Pass& p) {
  if (p.settled || !p.event()) return;
  p.event.wait();
  if (p.bracketed) p.host_ms = hostNowMs() - p.start_ms;
  p.settled = true;
}

void ClPassTimer::settleAll() {
  for (auto& p : passes_) settle(p);
}

void ClPassTimer::addDeviceTime(const Pass& p, PassTimings& out) const {
  cl_ulong start = 0, end = 0;
  const bool ok = profilingTimes(p.event, start, end) && start != 0 && end > start && profilingHook() != "broken";
  if (ok)
    out.add(p.name, static_cast<double>(end - start) * 1e-6);
  else
    out.addMissing(p.name);
}

void ClPassTimer::collect(PassTimings& out) {
  for (auto& p : passes_) {
    if (!p.event()) continue;  // slot handed out but never enqueued
    if (mode_ == Mode::Unknown) learnQueue(p.event.getInfo<CL_EVENT_COMMAND_QUEUE>());
    if (mode_ == Mode::Host) {
      settle(p);
      out.add(p.name, p.host_ms, PassClock::Host);
    } else {
      p.event.wait();
      addDeviceTime(p, out);
    }
  }
  passes_.clear();
}

}  // namespace ml
