#pragma once
// GL_TIME_ELAPSED queries per named pass. begin()/end() must not nest (GL
// allows one active elapsed-time query). collect() waits for the results.
#include <epoxy/gl.h>

#include <string>
#include <utility>
#include <vector>

#include "host/util/PassTimings.hpp"

namespace ml {

class GlPassTimer {
 public:
  ~GlPassTimer();
  void begin(const std::string& name);
  void end();
  void collect(PassTimings& out);

 private:
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
