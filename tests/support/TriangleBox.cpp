#include "support/TriangleBox.hpp"

#include <algorithm>
#include <cmath>

namespace ml::test {
namespace {

// Do the triangle (relative to the box centre) and the box overlap along `axis`?
bool overlapOnAxis(const glm::dvec3 v[3], const glm::dvec3& half, const glm::dvec3& axis) {
  const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
  const double r = half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
  return std::min({p0, p1, p2}) <= r && std::max({p0, p1, p2}) >= -r;
}

}  // namespace

bool triangleOverlapsBox(const Triangle& t, const glm::dvec3& centre, const glm::dvec3& half) {
  const glm::dvec3 v[3] = {t.p[0] - centre, t.p[1] - centre, t.p[2] - centre};
  const glm::dvec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  // The box's face normals, the triangle's normal, and the nine edge cross products.
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 axis(0.0);
    axis[a] = 1.0;
    if (!overlapOnAxis(v, half, axis)) return false;
  }
  if (!overlapOnAxis(v, half, glm::cross(e[0], e[1]))) return false;
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 box_axis(0.0);
    box_axis[a] = 1.0;
    for (const auto& edge : e) {
      const glm::dvec3 axis = glm::cross(box_axis, edge);
      if (glm::dot(axis, axis) > 0.0 && !overlapOnAxis(v, half, axis)) return false;
    }
  }
  return true;
}

}  // namespace ml::test
