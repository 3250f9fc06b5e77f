#include "support/TestGl.hpp"

#include <memory>

namespace ml::test {
GlContext& glContext() {
  static std::unique_ptr<GlContext> ctx = createHeadlessContext();
  ctx->makeCurrent();
  return *ctx;
}
}  // namespace ml::test
