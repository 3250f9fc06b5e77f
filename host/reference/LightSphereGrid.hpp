#pragma once
// A uniform grid over the lights' spheres on the CPU, so that finding the
// lights that reach a point costs the lights near it, not all of them (the
// ray-traced reference evaluates direct light at every secondary hit, with up
// to millions of lights). Cells are about the mean light diameter, at most
// kMaxCells in all; each cell lists every light whose sphere's bounding box
// overlaps it (CSR: offsets + indices). forEachLight(p) visits a superset of
// the lights whose sphere contains p; the caller tests the distance.
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

class LightSphereGrid {
 public:
  static constexpr std::size_t kMaxCells = std::size_t(1) << 21;
  explicit LightSphereGrid(const std::vector<gpu::PointLight>& lights);

  template <class F>
  void forEachCandidate(const glm::vec3& p, F&& f) const {
    if (cells_.x == 0) return;
    const glm::vec3 c = glm::floor((p - origin_) * inv_cell_);
    // Written so that NaN coordinates land outside too.
    if (!(c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < cells_.x && c.y < cells_.y && c.z < cells_.z)) return;
    const std::size_t cell = std::size_t(c.x) + std::size_t(cells_.x) * (std::size_t(c.y) + std::size_t(cells_.y) * std::size_t(c.z));
    for (std::size_t i = offsets_[cell]; i < offsets_[cell + 1]; ++i) f(indices_[i]);
  }
  glm::uvec3 cells() const { return cells_; }
  std::size_t entries() const { return indices_.size(); }

 private:
  glm::vec3 origin_{0.0f}, inv_cell_{0.0f};
  glm::uvec3 cells_{0u};
  std::vector<std::size_t> offsets_;
  std::vector<std::uint32_t> indices_;
};

}  // namespace ml
