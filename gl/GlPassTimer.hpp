#pragma once
// Per-pass GL times. On hardware GPUs: GL_TIME_ELAPSED queries (begin()/end()
// must not nest). On software rasterisers (llvmpipe, softpipe) those queries
// do not cover the deferred rasterisation work, so there each pass is
// bracketed by glFinish() and timed on the host clock instead.
// $MANYLIGHTS_GL_TIMING=query|host forces one method; any other non-empty
// value is a UserError naming the variable (checked at start-up too).
#include <epoxy/gl.h>

#include <string>
#include <utility>
#include <vector>

#include "host/util/PassTimings.hpp"

namespace ml {

enum class GlTimingMode { Auto, Query, Host };
// $MANYLIGHTS_GL_TIMING: unset or empty -> Auto; throws UserError otherwise.
GlTimingMode glTimingModeFromEnv();

class GlPassTimer {
 public:
  GlPassTimer();
  ~GlPassTimer();
  bool usesHostClock() const { return host_clock_; }
  void begin(const std::string& name);
  void end();
  void collect(PassTimings& out);

 private:
  bool host_clock_ = false;
  double host_start_ms_ = 0;
  std::string host_name_;
  PassTimings host_done_;
  std::vector<GLuint> pool_;
  std::vector<std::pair<std::string, GLuint>> active_;
};

// RAII pass scope: { GlPassScope s(timer, "shade"); ...draw... }
class GlPassScope {
 public:
  GlPassScope(GlPassTimer* t, const std::string& name) : t_(t) {
    if (t_) t_->begin(name);
  }
  ~GlPassScope() {
    if (t_) t_->end();
  }
  GlPassScope(const GlPassScope&) = delete;
  GlPassScope& operator=(const GlPassScope&) = delete;

 private:
  GlPassTimer* t_;
};

}  // namespace ml
