#include "host/reference/LightSphereGrid.hpp"

#include <algorithm>
#include <cmath>

namespace ml {
namespace {

struct CellRange {
  glm::uvec3 lo, hi;  // inclusive
};

glm::vec3 centre(const gpu::PointLight& l) { return {l.position_radius.x, l.position_radius.y, l.position_radius.z}; }

}  // namespace

LightSphereGrid::LightSphereGrid(const std::vector<gpu::PointLight>& lights) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  double radius_sum = 0;
  for (const auto& l : lights) {
    const float r = l.position_radius.w;
    lo = glm::min(lo, centre(l) - r);
    hi = glm::max(hi, centre(l) + r);
    radius_sum += r;
  }
  if (lights.empty() || !(hi.x >= lo.x)) return;
  const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-6f));
  // Cells of about a light's diameter, shrunk in step until they fit kMaxCells.
  float cell = std::max(float(2.0 * radius_sum / lights.size()), 1e-6f * std::max(extent.x, std::max(extent.y, extent.z)));
  glm::dvec3 n;
  for (;; cell *= 1.26f) {
    n = glm::max(glm::ceil(glm::dvec3(extent) / double(cell)), glm::dvec3(1.0));
    if (n.x * n.y * n.z <= double(kMaxCells)) break;
  }
  cells_ = glm::uvec3(n);
  origin_ = lo;
  inv_cell_ = glm::vec3(cells_) / extent;
  const auto range = [&](const gpu::PointLight& l) {
    const float r = l.position_radius.w;
    const glm::vec3 a = glm::floor((centre(l) - r - origin_) * inv_cell_), b = glm::floor((centre(l) + r - origin_) * inv_cell_);
    const glm::vec3 top = glm::vec3(cells_) - 1.0f;
    return CellRange{glm::uvec3(glm::clamp(a, glm::vec3(0.0f), top)), glm::uvec3(glm::clamp(b, glm::vec3(0.0f), top))};
  };
  const std::size_t total = std::size_t(cells_.x) * cells_.y * cells_.z;
  offsets_.assign(total + 1, 0);
  const auto visit = [&](const CellRange& c, auto&& f) {
    for (unsigned z = c.lo.z; z <= c.hi.z; ++z)
      for (unsigned y = c.lo.y; y <= c.hi.y; ++y)
        for (unsigned x = c.lo.x; x <= c.hi.x; ++x) f(x + std::size_t(cells_.x) * (y + std::size_t(cells_.y) * z));
  };
  for (const auto& l : lights) visit(range(l), [&](std::size_t cell) { ++offsets_[cell + 1]; });
  for (std::size_t i = 0; i < total; ++i) offsets_[i + 1] += offsets_[i];
  indices_.resize(offsets_[total]);
  std::vector<std::size_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::uint32_t i = 0; i < lights.size(); ++i)
    visit(range(lights[i]), [&](std::size_t cell) { indices_[fill[cell]++] = i; });
}

}  // namespace ml
