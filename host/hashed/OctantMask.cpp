#include "host/hashed/OctantMask.hpp"

#include <algorithm>

#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {
namespace {

constexpr double kFarTerm = 1e300;  // outside a version's box: never within its radius

// Both versions' mask() terms per axis and half cell over the hull of their
// cell boxes, so that each cell's two masks are 16 sums (the same doubles
// as mask() gives); with listed_in_both also the cell test's terms per axis
// and cell (kFarTerm outside a version's box).
struct VersionTerms {
  CellBox hull;
  glm::ivec3 n, off;          // hull size; offsets of the y and z half-cell terms
  std::vector<double> g[2], cell[2];
  double r2[2];
  LightOctants octants[2];

  VersionTerms(const gpu::PointLight* const versions[2], const CellBox boxes[2], const CellBox& hull_box,
               const OctreeBounds& b, bool listed_in_both)
      : hull(hull_box), n(hull.hi - hull.lo + 1), off(0, 2 * n.x, 2 * (n.x + n.y)) {
    for (int v = 0; v < 2; ++v) {
      const LightOctants& o = octants[v] = versions[v] ? LightOctants(*versions[v], b) : LightOctants();
      r2[v] = o.r2();
      g[v].resize(std::size_t(2 * (n.x + n.y + n.z)));
      for (int a = 0; a < 3; ++a) o.axisTerms(a, hull.lo[a], n[a], &g[v][std::size_t(off[a])]);
      if (!listed_in_both) continue;
      cell[v].resize(std::size_t(n.x + n.y + n.z));
      double* ct = cell[v].data();
      for (int a = 0; a < 3; ++a) {
        o.cellTerms(a, hull.lo[a], n[a], ct);
        for (int k = 0; k < n[a]; ++k)
          if (hull.lo[a] + k < boxes[v].lo[a] || hull.lo[a] + k > boxes[v].hi[a]) ct[k] = kFarTerm;
        ct += n[a];
      }
    }
  }
  // Version v's cell test on hull row (y, z) without the x term: sums only
  // grow with it (rounding is monotonic), so a miss here misses every cell.
  bool rowUnlisted(int v, int y, int z) const {
    return (0.0 + cell[v][std::size_t(n.x + y)]) + cell[v][std::size_t(n.x + n.y + z)] >= r2[v];
  }
  bool unlisted(int v, int x, int y, int z) const {
    return (cell[v][std::size_t(x)] + cell[v][std::size_t(n.x + y)]) + cell[v][std::size_t(n.x + n.y + z)] >= r2[v];
  }
  // Version v reaches no octant of any cell of row (y, z).
  bool rowMisses(int v, int y, int z) const {
    const double* gv = g[v].data();
    const std::size_t iy = std::size_t(off.y + 2 * y), iz = std::size_t(off.z + 2 * z);
    return std::min(gv[iy], gv[iy + 1]) + std::min(gv[iz], gv[iz + 1]) >= r2[v];
  }
  // Version v reaches all 8 octants of cell (x, y, z): the farthest octant's sum is below the radius.
  bool allEight(int v, int x, int y, int z) const {
    const double* gv = g[v].data();
    const std::size_t ix = std::size_t(2 * x), iy = std::size_t(off.y + 2 * y), iz = std::size_t(off.z + 2 * z);
    return (std::max(gv[ix], gv[ix + 1]) + std::max(gv[iy], gv[iy + 1])) + std::max(gv[iz], gv[iz + 1]) < r2[v];
  }
  std::uint8_t mask(int v, int x, int y, int z) const {
    const double* gv = g[v].data();
    return eightSumsBelow(gv + 2 * x, gv + off.y + 2 * y, gv + off.z + 2 * z, r2[v]);
  }
};

// The per-cell test: version 1's mask of hull cell (x, y, z) when it
// differs from version 0's, else none.
bool cellChanged(const VersionTerms& vt, int x, int y, int z, const GeometryMask* geometry, std::uint8_t& new_mask) {
  // All 8 octants in both versions: equal masks, unless geometry reduces
  // them (each version's sphere meets the octant boxes differently) in a
  // cell that has octant boxes.
  const bool all8 = vt.allEight(0, x, y, z) && vt.allEight(1, x, y, z);
  if (all8 && !geometry) return false;
  const glm::uvec3 cell(vt.hull.lo + glm::ivec3(x, y, z));
  const GeometryMask::Box* cell_box = nullptr;
  const GeometryMask::OctantBoxes* boxes = geometry ? geometry->octantBoxes(cell, cell_box) : nullptr;
  if (all8 && !boxes) return false;
  std::uint8_t ma = vt.mask(0, x, y, z), mb = vt.mask(1, x, y, z);
  if (boxes) {
    ma = vt.octants[0].onGeometry(ma, *boxes, *cell_box);
    mb = vt.octants[1].onGeometry(mb, *boxes, *cell_box);
  }
  new_mask = mb;
  return ma != mb;
}

}  // namespace

void appendOctantChanges(const gpu::PointLight* old_version, const gpu::PointLight* new_version,
                         std::uint32_t light, const OctreeBounds& b, bool listed_in_both,
                         const GeometryMask* geometry, std::vector<OctantChange>& out) {
  const CellBox boxes[2] = {old_version ? lightCellBox(*old_version, b) : CellBox{},
                            new_version ? lightCellBox(*new_version, b) : CellBox{}};
  const CellBox &ba = boxes[0], &bb = boxes[1];
  if (ba.empty() && bb.empty()) return;
  const CellBox hull = ba.empty()   ? bb
                       : bb.empty() ? ba
                                    : CellBox{glm::min(ba.lo, bb.lo), glm::max(ba.hi, bb.hi)};
  const gpu::PointLight* const versions[2] = {old_version, new_version};
  const VersionTerms vt(versions, boxes, hull, b, listed_in_both);
  const glm::ivec3 n = vt.n;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y) {
      // With listed_in_both, cells either version is not listed in are skipped.
      if (listed_in_both ? vt.rowUnlisted(0, y, z) || vt.rowUnlisted(1, y, z)
                         : vt.rowMisses(0, y, z) && vt.rowMisses(1, y, z))
        continue;
      for (int x = 0; x < n.x; ++x) {
        if (listed_in_both && (vt.unlisted(0, x, y, z) || vt.unlisted(1, x, y, z))) continue;
        std::uint8_t mask;
        if (cellChanged(vt, x, y, z, geometry, mask))
          out.push_back({nodeKey(b.depth, glm::uvec3(hull.lo + glm::ivec3(x, y, z))), light, mask});
      }
    }
}

}  // namespace ml::hashed
