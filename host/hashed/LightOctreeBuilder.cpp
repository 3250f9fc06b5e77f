#include "host/hashed/LightOctreeBuilder.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace ml::hashed {
namespace {

// Grid states: the flood fill only tests each cell once.
constexpr std::uint8_t kOutside = 0, kAssumedIn = 1, kTestedIn = 2;

struct Grid {
  glm::ivec3 lo, n;
  std::uint8_t* cells;
  std::size_t index(const glm::ivec3& p) const {
    return std::size_t(p.x - lo.x) + std::size_t(n.x) * (std::size_t(p.y - lo.y) + std::size_t(n.y) * std::size_t(p.z - lo.z));
  }
  bool filled(const glm::ivec3& p) const { return cells[index(p)] != kOutside; }
};

struct TreeBuilder {
  const Grid& grid;
  glm::dvec3 centre;
  unsigned depth;
  std::vector<LightNode>& out;

  // Axis distance from the centre to cell k.
  double axisDist(int a, int k) const {
    const double c = centre[a];
    return std::max({0.0, double(k) - c, c - double(k + 1)});
  }

  void node(unsigned t, const glm::ivec3& coord) {
    const int shift = int(depth - t);
    const glm::ivec3 rlo = coord << shift, rhi = ((coord + 1) << shift) - 1;
    const glm::ivec3 glo = grid.lo, ghi = grid.lo + grid.n - 1;
    const glm::ivec3 ilo = glm::max(rlo, glo), ihi = glm::min(rhi, ghi);
    if (ilo.x > ihi.x || ilo.y > ihi.y || ilo.z > ihi.z) {
      out.push_back(LightNode::Empty);
      return;
    }
    glm::ivec3 closest;
    for (int a = 0; a < 3; ++a)
      closest[a] = int(std::clamp(std::floor(centre[a]), double(ilo[a]), double(ihi[a])));
    if (!grid.filled(closest)) {
      out.push_back(LightNode::Empty);
      return;
    }
    if (shift == 0) {
      out.push_back(LightNode::Full);
      return;
    }
    const bool inside = ilo == rlo && ihi == rhi;
    if (inside) {
      glm::ivec3 farthest;
      for (int a = 0; a < 3; ++a) farthest[a] = axisDist(a, ilo[a]) >= axisDist(a, ihi[a]) ? ilo[a] : ihi[a];
      if (grid.filled(farthest)) {
        out.push_back(LightNode::Full);
        return;
      }
    }
    out.push_back(LightNode::Branch);
    for (int k = 0; k < 8; ++k) node(t + 1, coord * 2 + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  }
};

}  // namespace

LightOctree buildLightOctree(const gpu::PointLight& light, std::uint32_t index, const OctreeBounds& b,
                             LightGridScratch& scratch) {
  LightOctree lo;
  lo.light = index;
  const CellBox box = lightCellBox(light, b);
  if (box.empty()) return lo;
  const glm::dvec3 c = b.toCells({light.position_radius.x, light.position_radius.y, light.position_radius.z});
  const double r = b.radiusCells(light.position_radius.w);
  const double eps = b.eps_cells;

  // The minimal grid: the cell box per axis (the thesis takes the enclosing
  // cube; the box holds the same filled cells with fewer empty ones).
  Grid g{box.lo, box.hi - box.lo + 1, nullptr};
  const std::size_t count = std::size_t(g.n.x) * std::size_t(g.n.y) * std::size_t(g.n.z);
  scratch.grid.assign(count, kAssumedIn);
  g.cells = scratch.grid.data();
  auto& q = scratch.queue;
  q.clear();
  auto outside = [&](const glm::ivec3& p) { return !sphereOverlapsCells(c, r, p, p, eps); };
  auto visit = [&](const glm::ivec3& p) {
    std::uint8_t& s = g.cells[g.index(p)];
    if (s != kAssumedIn) return;
    if (outside(p)) {
      s = kOutside;
      q.push_back(std::uint32_t(g.index(p)));
    } else {
      s = kTestedIn;
    }
  };
  for (int k = 0; k < 8; ++k)
    visit({k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z});
  for (std::size_t head = 0; head < q.size(); ++head) {
    const std::uint32_t i = q[head];
    const glm::ivec3 p(box.lo.x + int(i % std::uint32_t(g.n.x)), box.lo.y + int((i / std::uint32_t(g.n.x)) % std::uint32_t(g.n.y)),
                       box.lo.z + int(i / (std::uint32_t(g.n.x) * std::uint32_t(g.n.y))));
    for (int a = 0; a < 3; ++a)
      for (int s = -1; s <= 1; s += 2) {
        glm::ivec3 nb = p;
        nb[a] += s;
        if (nb[a] < box.lo[a] || nb[a] > box.hi[a]) continue;
        visit(nb);
      }
  }
  lo.filled_cells = count - q.size();
  if (lo.filled_cells == 0) return lo;

  unsigned k = 0;
  while ((box.lo.x >> k) != (box.hi.x >> k) || (box.lo.y >> k) != (box.hi.y >> k) || (box.lo.z >> k) != (box.hi.z >> k))
    ++k;
  lo.root_depth = b.depth - k;
  lo.root = glm::uvec3(box.lo >> int(k));
  lo.nodes.reserve(count / 2 + 16);
  TreeBuilder tb{g, c, b.depth, lo.nodes};
  tb.node(lo.root_depth, glm::ivec3(lo.root));
  lo.nodes.shrink_to_fit();
  return lo;
}

std::vector<LightOctree> buildLightOctrees(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b) {
  std::vector<LightOctree> out(lights.size());
  if (lights.size() < 256) {  // less work than waking the worker threads
    LightGridScratch s;
    for (std::size_t i = 0; i < lights.size(); ++i) out[i] = buildLightOctree(lights[i], std::uint32_t(i), b, s);
    return out;
  }
  tbb::enumerable_thread_specific<LightGridScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 16), [&](const auto& range) {
    LightGridScratch& s = scratch.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      out[i] = buildLightOctree(lights[i], std::uint32_t(i), b, s);
  });
  return out;
}

}  // namespace ml::hashed
