#pragma once
// Exact triangle / axis-aligned box overlap (separating axis theorem,
// Akenine-Moeller 2001): the ground truth for "the surface crosses this voxel".
// Touching counts as overlapping; callers shrink or grow the box to ask
// "crosses the interior" or "lies within a margin".
#include <glm/glm.hpp>

namespace ml::test {

struct Triangle {
  glm::dvec3 p[3];
};

bool triangleOverlapsBox(const Triangle& t, const glm::dvec3& centre, const glm::dvec3& half);

}  // namespace ml::test
