#pragma once
// Collects the CL commands of named passes and turns them into times.
//
// Where the device's profiling clock works (deviceProfilingWorks), a pass's
// time is its CL_PROFILING_COMMAND_START..END (queueing delay excluded) and
// nothing waits. Where it does not (Mesa rusticl 22.x reports the constants
// 0, 1, 2, 3 as QUEUED..END), each timed pass is bracketed by finish calls on
// its queue and timed on the host clock, marked PassClock::Host: that adds
// launch overhead and removes the overlap of host work with the device's,
// so host-clock times are comparable only with each other. A device that
// claims a working clock but gives an event no usable times (an error,
// START == 0 or END <= START) leaves that pass missing (NaN), never 0.
//
// Usage: hand `next(name)` straight to the enqueue call,
//   q.enqueueNDRangeKernel(k, ..., nullptr, timer.next("pass"));
// next() returns a Slot that converts to the cl::Event* the call takes; its
// destructor, right after the enqueue returns, is where a host-clock pass is
// waited for and stamped. A Slot converted and kept for a later enqueue still
// works, but its host-clock end stamp then falls at the next next()/collect().
//
// Test hook: $MANYLIGHTS_TEST_PROFILING=host pretends every device's clock is
// unusable (host clock); =broken pretends it works but every event's profiling
// fails (missing times).
#include <CL/opencl.hpp>

#include <cstddef>
#include <deque>
#include <string>

#include "host/util/PassTimings.hpp"

namespace ml {

// Whether `device`'s profiling clock advances with real time: two commands
// with a host sleep between them must be that far apart on the device clock
// (START/END that are constants or zeros fail). Probed once per device per
// process on a queue of its own in `context`; the test hook is not cached.
bool deviceProfilingWorks(const cl::Context& context, const cl::Device& device);

class ClPassTimer {
 public:
  class Slot {
   public:
    Slot(std::nullptr_t) {}  // NOLINT: lets `timer ? timer->next(n) : nullptr` compile
    Slot(Slot&& o) noexcept : timer_(o.timer_), index_(o.index_) { o.timer_ = nullptr; }
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;
    Slot& operator=(Slot&&) = delete;
    ~Slot() {
      if (timer_) timer_->enqueued(index_);
    }
    operator cl::Event*() const { return timer_ ? &timer_->passes_[index_].event : nullptr; }  // NOLINT

   private:
    friend class ClPassTimer;
    Slot(ClPassTimer* t, std::size_t i) : timer_(t), index_(i) {}
    ClPassTimer* timer_ = nullptr;
    std::size_t index_ = 0;
  };

  ClPassTimer() = default;
  // Knowing the queue up front also brackets the very first host-clock pass.
  explicit ClPassTimer(const cl::CommandQueue& queue) { learnQueue(queue); }

  // The event slot for pass `name`, to hand to one enqueue call.
  Slot next(const std::string& name);
  // A command enqueued without next(): device time where the clock works;
  // missing on a host-clock device (its start was not bracketed).
  void record(const std::string& name, const cl::Event& e);
  // Waits for all passes, adds their times to `out` in order, and clears.
  void collect(PassTimings& out);
  bool empty() const { return passes_.empty(); }
  // Whether this timer has found its queue's device clock unusable.
  bool usesHostClock() const { return mode_ == Mode::Host; }

 private:
  enum class Mode { Unknown, Device, Host };
  struct Pass {
    std::string name;
    cl::Event event;
    double start_ms = 0;                    // host clock, when next() handed the slot out
    double host_ms = PassTimings::kMissing;  // host-clock time, once waited for
    bool settled = false;                   // host clock: waited for and stamped
    bool bracketed = true;                  // false: record()ed, start unknown
  };
  std::deque<Pass> passes_;  // deque: Slot event pointers stay valid
  cl::CommandQueue queue_;
  Mode mode_ = Mode::Unknown;

  void enqueued(std::size_t index) noexcept;
  void learnQueue(const cl::CommandQueue& queue);
  void settle(Pass& p);
  void settleAll();
  void addDeviceTime(const Pass& p, PassTimings& out) const;
};

}  // namespace ml
