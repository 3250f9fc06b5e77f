#include "host/hashed/OctantMask.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "host/hashed/SceneOctree.hpp"

namespace ml::hashed {
namespace {
constexpr double kFarTerm = 1e300;  // outside a version's box: never within its radius
}  // namespace

OctantTables::OctantTables(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b)
    : lights_(lights.size()) {
  std::size_t total = 0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const CellBox box = lightCellBox(lights[i], b);
    Light& l = lights_[i];
    l.lo = box.lo;
    l.n = box.empty() ? glm::ivec3(0) : box.hi - box.lo + 1;
    l.at = total;
    total += std::size_t(2 * (l.n.x + l.n.y + l.n.z));
  }
  terms_.resize(total);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 1024), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const LightOctants o(lights[i], b);
      Light& l = lights_[i];
      l.r2 = o.r2();
      double* g = &terms_[l.at];
      for (int a = 0; a < 3; ++a) {
        o.axisTerms(a, l.lo[a], l.n[a], g);
        g += 2 * l.n[a];
      }
    }
  });
}

void appendOctantChanges(const gpu::PointLight* old_version, const gpu::PointLight* new_version,
                         std::uint32_t light, const OctreeBounds& b, bool listed_in_both,
                         const GeometryMask* geometry, std::vector<OctantChange>& out) {
  const CellBox ba = old_version ? lightCellBox(*old_version, b) : CellBox{};
  const CellBox bb = new_version ? lightCellBox(*new_version, b) : CellBox{};
  if (ba.empty() && bb.empty()) return;
  const CellBox hull = ba.empty()   ? bb
                       : bb.empty() ? ba
                                    : CellBox{glm::min(ba.lo, bb.lo), glm::max(ba.hi, bb.hi)};
  // Per version, axis and half cell of the hull, the terms of mask(): each
  // cell's two masks are then 16 sums (the same doubles as mask() gives).
  const glm::ivec3 n = hull.hi - hull.lo + 1;
  const glm::ivec3 off(0, 2 * n.x, 2 * (n.x + n.y));
  const std::size_t terms = std::size_t(2 * (n.x + n.y + n.z));
  // With listed_in_both, also the cell test's terms (kFar outside a version's box).
  const std::size_t cterms = listed_in_both ? std::size_t(n.x + n.y + n.z) : 0;
  std::vector<double> g(2 * terms + 2 * cterms);
  double r2[2];
  LightOctants octants[2];
  for (int v = 0; v < 2; ++v) {
    const gpu::PointLight* version = v == 0 ? old_version : new_version;
    const LightOctants& o = octants[v] = version ? LightOctants(*version, b) : LightOctants();
    r2[v] = o.r2();
    for (int a = 0; a < 3; ++a) o.axisTerms(a, hull.lo[a], n[a], &g[std::size_t(v) * terms + std::size_t(off[a])]);
    if (!listed_in_both) continue;
    const CellBox& box = v == 0 ? ba : bb;
    double* ct = &g[2 * terms + std::size_t(v) * cterms];
    for (int a = 0; a < 3; ++a) {
      o.cellTerms(a, hull.lo[a], n[a], ct);
      for (int k = 0; k < n[a]; ++k)
        if (hull.lo[a] + k < box.lo[a] || hull.lo[a] + k > box.hi[a]) ct[k] = kFarTerm;
      ct += n[a];
    }
  }
  const double* ga = g.data();
  const double* gb = g.data() + terms;
  const double* ca = g.data() + 2 * terms;  // cell terms: x at 0, y at n.x, z at n.x + n.y
  const double* cb = ca + cterms;
  auto rowMisses = [](const double* gv, std::size_t iy, std::size_t iz, double r) {  // no octant of any cell
    return std::min(gv[iy], gv[iy + 1]) + std::min(gv[iz], gv[iz + 1]) >= r;
  };
  const std::size_t cz0 = std::size_t(n.x + n.y);  // cell terms of y start at n.x, of z here
  // With listed_in_both, a cell either version is not listed in (the cell
  // test: the octant terms' sums over the whole cell) is skipped.
  auto unlisted = [&](std::size_t cx, std::size_t cy, std::size_t cz) {
    return (ca[cx] + ca[cy]) + ca[cz] >= r2[0] || (cb[cx] + cb[cy]) + cb[cz] >= r2[1];
  };
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y) {
      const std::size_t iy = std::size_t(off.y + 2 * y), iz = std::size_t(off.z + 2 * z);
      const std::size_t cy = std::size_t(n.x + y), cz = cz0 + std::size_t(z);
      // Sums only grow with the x term (rounding is monotonic): a row where
      // they miss without it misses in every cell.
      if (listed_in_both ? (0.0 + ca[cy]) + ca[cz] >= r2[0] || (0.0 + cb[cy]) + cb[cz] >= r2[1]
                         : rowMisses(ga, iy, iz, r2[0]) && rowMisses(gb, iy, iz, r2[1]))
        continue;
      // The farthest octant's sum: below the radius, every octant is reached.
      const double fya = std::max(ga[iy], ga[iy + 1]), fza = std::max(ga[iz], ga[iz + 1]);
      const double fyb = std::max(gb[iy], gb[iy + 1]), fzb = std::max(gb[iz], gb[iz + 1]);
      for (int x = 0; x < n.x; ++x) {
        if (listed_in_both && unlisted(std::size_t(x), cy, cz)) continue;
        const std::size_t ix = std::size_t(2 * x);
        // All 8 octants in both versions: equal masks, unless geometry
        // reduces them (each version's sphere meets the octant boxes
        // differently) in a cell that has octant boxes.
        const bool all8 = (std::max(ga[ix], ga[ix + 1]) + fya) + fza < r2[0] &&
                          (std::max(gb[ix], gb[ix + 1]) + fyb) + fzb < r2[1];
        if (all8 && !geometry) continue;
        const glm::uvec3 cell(hull.lo + glm::ivec3(x, y, z));
        const GeometryMask::Box* cell_box = nullptr;
        const GeometryMask::OctantBoxes* boxes = geometry ? geometry->octantBoxes(cell, cell_box) : nullptr;
        if (all8 && !boxes) continue;
        std::uint8_t ma = octantBits(ga + ix, ga + iy, ga + iz, r2[0]);
        std::uint8_t mb = octantBits(gb + ix, gb + iy, gb + iz, r2[1]);
        if (boxes) {
          ma = octants[0].onGeometry(ma, *boxes, *cell_box);
          mb = octants[1].onGeometry(mb, *boxes, *cell_box);
        }
        if (ma != mb) out.push_back({nodeKey(b.depth, cell), light, mb});
      }
    }
}

}  // namespace ml::hashed
