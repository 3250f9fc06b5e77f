#pragma once
// GL error checking. glCheck() drains glGetError after a group of calls and
// throws naming the operation; the debug-output callback (installed on every
// context) records errors reported by the driver so glCheck() can name them.
#include <epoxy/gl.h>

#include <string>

namespace ml {

// Throws std::runtime_error("GL error in <what>: GL_INVALID_OPERATION ...") if
// glGetError reports anything or the debug callback saw an error since the last check.
void glCheck(const char* what);
void installGlDebugOutput();
std::string glErrorName(GLenum e);

}  // namespace ml
