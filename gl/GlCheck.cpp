#include "gl/GlCheck.hpp"

#include <spdlog/spdlog.h>

#include <mutex>
#include <stdexcept>

namespace ml {
namespace {
std::mutex g_mutex;
std::string g_last_debug_error;

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                               const GLchar* message, const void*) {
  (void)source;
  (void)id;
  std::string msg(message, length > 0 ? static_cast<size_t>(length) : std::char_traits<char>::length(message));
  if (type == GL_DEBUG_TYPE_ERROR) {
    std::lock_guard lock(g_mutex);
    g_last_debug_error = msg;
  } else if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM) {
    spdlog::debug("GL: {}", msg);
  }
}
}  // namespace

std::string glErrorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: return "GL error " + std::to_string(e);
  }
}

void glCheck(const char* what) {
  GLenum first = glGetError();
  while (glGetError() != GL_NO_ERROR) {
  }
  std::string debug;
  {
    std::lock_guard lock(g_mutex);
    debug.swap(g_last_debug_error);
  }
  if (first != GL_NO_ERROR)
    throw std::runtime_error(std::string("GL error in ") + what + ": " + glErrorName(first) +
                             (debug.empty() ? "" : " (" + debug + ")"));
}

void installGlDebugOutput() {
  if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43) return;
  glEnable(GL_DEBUG_OUTPUT);
#ifndef NDEBUG
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
#endif
  glDebugMessageCallback(onDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

}  // namespace ml
