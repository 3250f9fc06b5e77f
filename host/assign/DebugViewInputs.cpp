#include "host/assign/DebugViewInputs.hpp"

#include "host/assign/ExactLowerBound.hpp"

namespace ml {

bool DebugViewInputs::worldAt(unsigned x, unsigned y, glm::vec3& world) const {
  return windowToWorld(depth[std::size_t(y) * width + x], x, y, unproject, world);
}

}  // namespace ml
