#include "gl/GlPassTimer.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>

#include "gl/GlCheck.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {
double nowMs() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

GlTimingMode glTimingModeFromEnv() {
  const char* force = std::getenv("MANYLIGHTS_GL_TIMING");
  if (!force || !*force) return GlTimingMode::Auto;
  if (std::strcmp(force, "host") == 0) return GlTimingMode::Host;
  if (std::strcmp(force, "query") == 0) return GlTimingMode::Query;
  throw UserError("MANYLIGHTS_GL_TIMING: expected query or host (or unset), got '" + std::string(force) + "'");
}

GlPassTimer::GlPassTimer() {
  const GlTimingMode mode = glTimingModeFromEnv();
  if (mode != GlTimingMode::Auto) {
    host_clock_ = mode == GlTimingMode::Host;
  } else {
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    host_clock_ = r && (std::strstr(r, "llvmpipe") || std::strstr(r, "softpipe") || std::strstr(r, "SWR"));
  }
}

GlPassTimer::~GlPassTimer() {
  for (auto& [n, q] : active_) pool_.push_back(q);
  if (!pool_.empty()) glDeleteQueries(static_cast<GLsizei>(pool_.size()), pool_.data());
}

void GlPassTimer::begin(const std::string& name) {
  if (host_clock_) {
    glFinish();
    host_name_ = name;
    host_start_ms_ = nowMs();
    return;
  }
  GLuint q = 0;
  if (pool_.empty()) {
    glCreateQueries(GL_TIME_ELAPSED, 1, &q);
  } else {
    q = pool_.back();
    pool_.pop_back();
  }
  glBeginQuery(GL_TIME_ELAPSED, q);
  active_.emplace_back(name, q);
}

void GlPassTimer::end() {
  if (host_clock_) {
    glFinish();
    host_done_.add(host_name_, nowMs() - host_start_ms_, PassClock::Host);
    return;
  }
  glEndQuery(GL_TIME_ELAPSED);
}

void GlPassTimer::collect(PassTimings& out) {
  out.merge(host_done_);
  host_done_.clear();
  for (auto& [name, q] : active_) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &ns);
    out.add(name, static_cast<double>(ns) * 1e-6);
    pool_.push_back(q);
  }
  active_.clear();
  glCheck("collecting GL timer queries");
}

}  // namespace ml
