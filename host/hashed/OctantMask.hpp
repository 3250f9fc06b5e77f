#pragma once
// Octant masks: which eighths of a deepest cell a light reaches (beyond the
// thesis). A leaf's light list is charged every light that reaches any part
// of its cell; at the deepest depth each index list entry also carries the 8
// bits saying which of the cell's octants (half-size cells) the light's
// sphere overlaps, and the lookup skips entries whose bit for the point's
// octant is clear. That gives the light counts of half the node size for the
// index memory of the full one. Contract:
//  - An entry is `light | mask << kEntryLightBits`: lights are limited to
//    kMaxHashedLights (checked by HashedStructure).
//  - The mask of a leaf at the deepest depth is octants().mask(cell); a
//    shallower leaf (merged: every light in its set reaches each of its
//    deepest cells, so each octant) gets kAllOctants, as does every leaf
//    when masks are off. So a leaf's entries are a function of its key, its
//    light set and the current lights, which is what keeps updates equal to
//    fresh builds.
//  - The point's octant is bit (2q) & 1 per axis of the float cell
//    coordinate q (exact: doubling a float is exact), octant k = x + 2y + 4z;
//    the overlap test widens each octant by the bounds' eps like the cell
//    test, so float rounding of q never drops a light that contains the point.
//  - With a geometry mask, bit k is also cleared where the sphere misses
//    octant k's geometry box (GeometryMask::octantBoxes(), widened by eps):
//    a surface point in octant k lies in that box, so no shaded point there
//    is lost, and lights that reach the octant but not its surfaces (a floor
//    octant under a light above the floor's thin slab) are skipped. Cells
//    without octant boxes keep the plain bits. Builds and updates apply the
//    same test (LightOctants::onGeometry()).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "host/hashed/EightSums.hpp"
#include "host/hashed/GeometryMask.hpp"
#include "host/hashed/OctreeBounds.hpp"

namespace ml::hashed {

constexpr unsigned kEntryLightBits = 24;
constexpr std::uint32_t kMaxHashedLights = (1u << kEntryLightBits) - 1u;
constexpr std::uint32_t kEntryLightMask = (1u << kEntryLightBits) - 1u;
constexpr std::uint8_t kAllOctants = 0xFF;

inline std::uint32_t packEntry(std::uint32_t light, std::uint8_t mask) {
  return light | (std::uint32_t(mask) << kEntryLightBits);
}
inline std::uint32_t entryLight(std::uint32_t e) { return e & kEntryLightMask; }
inline std::uint8_t entryMask(std::uint32_t e) { return std::uint8_t(e >> kEntryLightBits); }

// The octant of a point given as its float cell coordinate (the lookups' q).
inline unsigned octantOf(const glm::vec3& q) {
  const glm::uvec3 h = glm::uvec3(q * 2.0f) & 1u;
  return h.x + 2u * h.y + 4u * h.z;
}

// Squared distance from `c` to half cell h of cell `cell` on one axis,
// [cell + h/2, cell + h/2 + 1/2] widened by eps. Every mask is made of these
// terms summed in axis order, so any two ways of computing a mask agree.
inline double halfCellGap2(double c, int cell, int h, double eps) {
  const double lo = double(cell) + 0.5 * double(h) - eps, hi = lo + (0.5 + 2.0 * eps);
  const double v = std::max(std::max(lo - c, c - hi), 0.0);
  return v * v;
}

// One light's octant masks over the deepest cells.
class LightOctants {
 public:
  LightOctants() = default;  // reaches nothing
  LightOctants(const gpu::PointLight& light, const OctreeBounds& bounds)
      : c_(bounds.toCells({light.position_radius.x, light.position_radius.y, light.position_radius.z})),
        r2_(bounds.radiusCells(light.position_radius.w) * bounds.radiusCells(light.position_radius.w)),
        eps_(bounds.eps_cells) {}
  // Bit k: the light's sphere overlaps octant k of `cell`, widened by eps
  // (squared per-axis gaps summed in axis order, as sphereOverlapsCells()).
  // Zero for every cell outside lightCellBox().
  std::uint8_t mask(const glm::ivec3& cell) const {
    double g[3][2];
    for (int a = 0; a < 3; ++a) axisTerms(a, cell[a], 1, g[a]);
    return eightSumsBelow(g[0], g[1], g[2], r2_);
  }
  // mask()'s terms for `n` cells from `lo` along `axis`, 2 per cell: tables
  // of them give the same masks for many cells.
  void axisTerms(int axis, int lo, int n, double* out) const {
    for (int k = 0; k < n; ++k)
      for (int h = 0; h < 2; ++h) *out++ = halfCellGap2(c_[axis], lo + k, h, eps_);
  }
  // sphereOverlapsCells()'s terms for `n` cells from `lo` along `axis`
  // (the cell test: a light is listed in exactly the cells it passes).
  void cellTerms(int axis, int lo, int n, double* out) const {
    for (int k = 0; k < n; ++k) *out++ = axisGap2(c_[axis], lo + k, lo + k, eps_);
  }
  // `bits` less the octants whose geometry box (widened by eps) the sphere
  // misses, or that hold no geometry.
  std::uint8_t onGeometry(std::uint8_t bits, const GeometryMask::OctantBoxes& boxes) const {
    // All 8 without branches (an empty box's lo > hi only grows its gap).
    unsigned reached = 0;
    for (unsigned k = 0; k < 8; ++k)
      reached |= unsigned(!boxes.empty(k) && boxGap2(boxes.lo[k], boxes.hi[k]) < r2_) << k;
    return std::uint8_t(bits & reached);
  }
  // The same, given the cell's geometry box (which holds the octant boxes):
  // a sphere that misses it misses them all, one that holds it (widened by
  // eps alike, so the sums bound the octant boxes' exactly) reaches every
  // non-empty one; only the other cells test the 8 boxes.
  std::uint8_t onGeometry(std::uint8_t bits, const GeometryMask::OctantBoxes& boxes,
                          const GeometryMask::Box& cell_box) const {
    if (!bits) return bits;
    double near = 0.0, far = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double lo = cell_box.lo[a] - eps_, hi = cell_box.hi[a] + eps_;
      const double dn = std::max(std::max(lo - c_[a], c_[a] - hi), 0.0), df = std::max(c_[a] - lo, hi - c_[a]);
      near += dn * dn;
      far += df * df;
    }
    if (near >= r2_) return 0;
    if (far >= r2_) return onGeometry(bits, boxes);
    unsigned filled = 0;
    for (unsigned k = 0; k < 8; ++k) filled |= unsigned(!boxes.empty(k)) << k;
    return std::uint8_t(bits & filled);
  }
  double r2() const { return r2_; }

 private:
  // Squared distance from the centre to the box [lo - eps, hi + eps].
  double boxGap2(const glm::vec3& lo, const glm::vec3& hi) const {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double v = std::max(std::max((double(lo[a]) - eps_) - c_[a], c_[a] - (double(hi[a]) + eps_)), 0.0);
      d2 += v * v;
    }
    return d2;
  }
  glm::dvec3 c_{0.0};  // centre, cells
  double r2_ = -1.0, eps_ = 0.0;
};

// A deepest cell where a light's octant mask changed.
struct OctantChange {
  std::uint64_t key;  // nodeKey(depth, cell)
  std::uint32_t light;
  std::uint8_t mask;  // the new version's
};
// The light index list word that such a change rewrites.
struct OctantRewrite {
  std::uint64_t key;
  std::uint32_t at, word;
};

// Appends the deepest cells whose mask for `light` differs between its old
// and new versions (null: the light did not exist / no longer exists), both
// masks reduced by `geometry` (null: none) as the build reduces them. With
// `listed_in_both`, only cells that both versions pass the cell test for:
// where an exact update without geometry-tight sets adds or removes the
// light (the cell test says where it is listed), the cell is a touched key
// and its entries are derived afresh anyway.
void appendOctantChanges(const gpu::PointLight* old_version, const gpu::PointLight* new_version,
                         std::uint32_t light, const OctreeBounds& bounds, bool listed_in_both,
                         const GeometryMask* geometry, std::vector<OctantChange>& out);

}  // namespace ml::hashed
