#pragma once
// One headless GL context per test process (EGL), current on the main thread.
#include "gl/GlContext.hpp"

namespace ml::test {
GlContext& glContext();
}
