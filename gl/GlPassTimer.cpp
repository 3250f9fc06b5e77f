#include "gl/GlPassTimer.hpp"

#include "gl/GlCheck.hpp"

namespace ml {

GlPassTimer::~GlPassTimer() {
  for (auto& [n, q] : active_) pool_.push_back(q);
  if (!pool_.empty()) glDeleteQueries(static_cast<GLsizei>(pool_.size()), pool_.data());
}

void GlPassTimer::begin(const std::string& name) {
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

void GlPassTimer::end() { glEndQuery(GL_TIME_ELAPSED); }

void GlPassTimer::collect(PassTimings& out) {
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
