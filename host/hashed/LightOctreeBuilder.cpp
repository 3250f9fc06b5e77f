#include "host/hashed/LightOctreeBuilder.hpp"


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
  glm::ivec3 centre_cell;  // floor(centre), clamped to the grid
  glm::dvec3 twice_centre;
  unsigned depth;
  std::vector<LightNode>& out;
  glm::ivec3 ghi;  // last grid cell

  void node(unsigned t, const glm::ivec3& coord) {
    const int size = 1 << (depth - t);
    nodeAt(coord * size, size);
  }

  // The node with min corner `rlo` and edge `size` (cells).
  void nodeAt(const glm::ivec3& rlo, int size) {
    const LightNode type = classifyNode(rlo, size, grid.lo, ghi, centre_cell, twice_centre,
                                        [this](const glm::ivec3& p) { return grid.filled(p); });
    out.push_back(type);
    if (type != LightNode::Branch) return;
    const int half = size / 2;
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 clo = rlo + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) * half;
      // Children outside the grid are empty: no call needed.
      if (clo.x > ghi.x || clo.y > ghi.y || clo.z > ghi.z || clo.x + half <= grid.lo.x ||
          clo.y + half <= grid.lo.y || clo.z + half <= grid.lo.z) {
        out.push_back(LightNode::Empty);
        continue;
      }
      nodeAt(clo, half);
    }
  }
};

// Counts of lit (kTestedIn, low 32 bits) and unlit (kOutside, high 32 bits)
// cells over every box of a grid, from its summed-volume table: sums[(x, y,
// z)] holds the counts over the cells before (x, y, z) on every axis.
struct GridCounts {
  glm::ivec3 lo, n;
  const std::uint64_t* sums;  // (n + 1)^3 entries
  std::uint64_t at(int x, int y, int z) const {
    return sums[std::size_t(x) + std::size_t(n.x + 1) * (std::size_t(y) + std::size_t(n.y + 1) * std::size_t(z))];
  }
  // Over the cells [a, b] (grid coordinates, inclusive).
  std::uint64_t box(const glm::ivec3& a, const glm::ivec3& b) const {
    const glm::ivec3 e = b + 1;
    return at(e.x, e.y, e.z) - at(a.x, e.y, e.z) - at(e.x, a.y, e.z) - at(e.x, e.y, a.z) + at(a.x, a.y, e.z) +
           at(a.x, e.y, a.z) + at(e.x, a.y, a.z) - at(a.x, a.y, a.z);
  }
};

GridCounts countGrid(const Grid& g, std::vector<std::uint64_t>& sums) {
  const glm::ivec3 n = g.n, m = n + 1;
  sums.assign(std::size_t(m.x) * std::size_t(m.y) * std::size_t(m.z), 0);
  auto at = [&](int x, int y, int z) -> std::uint64_t& {
    return sums[std::size_t(x) + std::size_t(m.x) * (std::size_t(y) + std::size_t(m.y) * std::size_t(z))];
  };
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        const std::uint8_t v = g.cells[g.index(g.lo + glm::ivec3(x, y, z))];
        const std::uint64_t c = v == kTestedIn ? 1u : v == kOutside ? std::uint64_t(1) << 32 : 0u;
        at(x + 1, y + 1, z + 1) = c + at(x, y + 1, z + 1) + at(x + 1, y, z + 1) + at(x + 1, y + 1, z) -
                                  at(x, y, z + 1) - at(x, y + 1, z) - at(x + 1, y, z) + at(x, y, z);
      }
  return {g.lo, n, sums.data()};
}

// Minimal octree of a grid whose cells are lit (kTestedIn), unlit
// (kOutside) or without geometry (kAssumedIn: may be taken either way);
// cells outside the grid are unlit. A node holding both a lit and an unlit
// cell is a branch, else one leaf: full when it holds a lit cell, else
// empty. The grid's box counts answer that per node in O(1), so only
// branches are descended into (walking every cell was the light octrees'
// largest cost at 0.5r).
struct GeometryTreeBuilder {
  const GridCounts& counts;
  unsigned depth;
  std::vector<LightNode>& out;

  void node(unsigned t, const glm::ivec3& coord) {
    const int shift = int(depth - t);
    const glm::ivec3 rlo = coord << shift, rhi = ((coord + 1) << shift) - 1;
    const glm::ivec3 glo = counts.lo, ghi = counts.lo + counts.n - 1;
    const glm::ivec3 ilo = glm::max(rlo, glo), ihi = glm::min(rhi, ghi);
    if (ilo.x > ihi.x || ilo.y > ihi.y || ilo.z > ihi.z) {
      out.push_back(LightNode::Empty);
      return;
    }
    const std::uint64_t c = counts.box(ilo - glo, ihi - glo);
    const bool lit = (c & 0xFFFFFFFFu) != 0;
    const bool unlit = (c >> 32) != 0 || ilo != rlo || ihi != rhi;
    if (!(lit && unlit)) {
      out.push_back(lit ? LightNode::Full : LightNode::Empty);
      return;
    }
    out.push_back(LightNode::Branch);
    for (int k = 0; k < 8; ++k) node(t + 1, coord * 2 + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  }
};

// Roots: the nodes at the deepest depth where the box spans at most 2 nodes
// per axis; `emit` appends a root's subtree, kept unless it is one empty leaf.
template <class F>
void forEachRoot(const CellBox& box, unsigned depth, LightOctree& lo, F&& emit) {
  unsigned k = 0;
  while ((box.hi.x >> k) - (box.lo.x >> k) > 1 || (box.hi.y >> k) - (box.lo.y >> k) > 1 ||
         (box.hi.z >> k) - (box.lo.z >> k) > 1)
    ++k;
  lo.root_depth = depth - k;
  const glm::ivec3 rlo = box.lo >> int(k), rhi = box.hi >> int(k);
  for (int z = rlo.z; z <= rhi.z; ++z)
    for (int y = rlo.y; y <= rhi.y; ++y)
      for (int x = rlo.x; x <= rhi.x; ++x) {
        const std::size_t at = lo.nodes.size();
        emit(glm::ivec3(x, y, z));
        if (lo.nodes.size() == at + 1 && lo.nodes[at] == LightNode::Empty) {
          lo.nodes.pop_back();
          continue;
        }
        lo.roots[lo.root_count] = glm::uvec3(x, y, z);
        lo.root_start[lo.root_count++] = std::uint32_t(at);
      }
  lo.nodes.shrink_to_fit();
}

bool sphereOverlapsBox(const glm::dvec3& c, double r, const GeometryMask::Box& b) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double v = c[a] < b.lo[a] ? b.lo[a] - c[a] : (c[a] > b.hi[a] ? c[a] - b.hi[a] : 0.0);
    d2 += v * v;
  }
  return d2 < r * r;
}

// A light's sphere in cell units, as every step below tests it.
struct Sphere {
  glm::dvec3 c;
  double r, eps;
};

// Whether the sphere reaches a cell's geometry box, and then (finer) one of
// its octants' boxes.
bool reachesCellGeometry(const Sphere& s, const GeometryMask::Box& cell_box, const GeometryMask::OctantBoxes& oct) {
  if (!sphereOverlapsBox(s.c, s.r, {cell_box.lo - s.eps, cell_box.hi + s.eps})) return false;
  for (unsigned k = 0; k < 8; ++k)
    if (!oct.empty(k) && sphereOverlapsBox(s.c, s.r, {glm::dvec3(oct.lo[k]) - s.eps, glm::dvec3(oct.hi[k]) + s.eps}))
      return true;
  return false;
}

// Geometry-tight cells: each cell with geometry is lit (kTestedIn) when the
// sphere reaches its geometry (reachesCellGeometry), else kOutside; cells
// without geometry stay kAssumedIn. Returns the lit count.
std::size_t markGeometryCells(const Sphere& s, const CellBox& box, const GeometryMask& geometry, Grid& g) {
  std::size_t lit = 0;
  for (int z = box.lo.z; z <= box.hi.z; ++z)
    for (int y = box.lo.y; y <= box.hi.y; ++y) {
      const auto [first, last] = geometry.rowCells(unsigned(y), unsigned(z), unsigned(box.lo.x), unsigned(box.hi.x));
      for (std::size_t i = first; i < last; ++i) {
        const bool in = reachesCellGeometry(s, geometry.cellBox(i), geometry.cellOctants(i));
        g.cells[g.index({int(geometry.cellX(i)), y, z})] = in ? kTestedIn : kOutside;
        lit += in;
      }
    }
  return lit;
}

// Plain cells: the sphere is convex, so the cells it misses are reached
// from the box's corners by a flood fill that tests each cell once, and
// every cell the fill does not reach is lit. Returns the lit count.
std::size_t floodOutsideCells(const Sphere& s, const CellBox& box, Grid& g, std::vector<std::uint32_t>& q) {
  q.clear();
  auto visit = [&](const glm::ivec3& p) {
    std::uint8_t& v = g.cells[g.index(p)];
    if (v != kAssumedIn) return;
    if (!sphereOverlapsCells(s.c, s.r, p, p, s.eps)) {
      v = kOutside;
      q.push_back(std::uint32_t(g.index(p)));
    } else {
      v = kTestedIn;
    }
  };
  for (int k = 0; k < 8; ++k)
    visit({k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z});
  const glm::uvec3 n(g.n);
  for (std::size_t head = 0; head < q.size(); ++head) {
    const std::uint32_t i = q[head];
    const glm::ivec3 p = box.lo + glm::ivec3(glm::uvec3(i % n.x, (i / n.x) % n.y, i / (n.x * n.y)));
    for (int a = 0; a < 3; ++a)
      for (int d = -1; d <= 1; d += 2) {
        glm::ivec3 nb = p;
        nb[a] += d;
        if (nb[a] >= box.lo[a] && nb[a] <= box.hi[a]) visit(nb);
      }
  }
  return std::size_t(n.x) * n.y * n.z - q.size();
}

}  // namespace

LightOctree buildLightOctree(const gpu::PointLight& light, std::uint32_t index, const OctreeBounds& b,
                             LightGridScratch& scratch, const GeometryMask* geometry) {
  LightOctree lo;
  lo.light = index;
  const CellBox box = lightCellBox(light, b);
  if (box.empty()) return lo;
  const Sphere s{b.toCells({light.position_radius.x, light.position_radius.y, light.position_radius.z}),
                 b.radiusCells(light.position_radius.w), b.eps_cells};

  // The minimal grid: the cell box per axis (the thesis takes the enclosing
  // cube; the box holds the same filled cells with fewer empty ones).
  Grid g{box.lo, box.hi - box.lo + 1, nullptr};
  const std::size_t count = std::size_t(g.n.x) * std::size_t(g.n.y) * std::size_t(g.n.z);
  scratch.grid.assign(count, kAssumedIn);
  g.cells = scratch.grid.data();
  lo.filled_cells = geometry ? markGeometryCells(s, box, *geometry, g) : floodOutsideCells(s, box, g, scratch.queue);
  if (lo.filled_cells == 0) return lo;
  if (geometry) {
    const GridCounts counts = countGrid(g, scratch.sums);
    GeometryTreeBuilder tb{counts, b.depth, lo.nodes};
    forEachRoot(box, b.depth, lo, [&](const glm::ivec3& root) { tb.node(lo.root_depth, root); });
    return lo;
  }
  lo.nodes.reserve(count / 2 + 16);
  const glm::ivec3 centre_cell(glm::clamp(glm::floor(s.c), glm::dvec3(box.lo), glm::dvec3(box.hi)));
  TreeBuilder tb{g, centre_cell, 2.0 * s.c, b.depth, lo.nodes, box.hi};
  forEachRoot(box, b.depth, lo, [&](const glm::ivec3& root) { tb.node(lo.root_depth, root); });
  return lo;
}

LightCells::LightCells(const gpu::PointLight& light, const OctreeBounds& b)
    : box_(lightCellBox(light, b)), depth_(b.depth) {
  if (box_.empty()) return;
  // As buildLightOctree() derives them.
  const glm::dvec3 c = b.toCells({light.position_radius.x, light.position_radius.y, light.position_radius.z});
  const double r = b.radiusCells(light.position_radius.w), eps = b.eps_cells;
  twice_centre_ = 2.0 * c;
  r2_ = r * r;
  centre_cell_ = glm::ivec3(glm::clamp(glm::floor(c), glm::dvec3(box_.lo), glm::dvec3(box_.hi)));
  const glm::ivec3 n = box_.hi - box_.lo + 1;
  axis_off_ = glm::ivec3(0, n.x, n.x + n.y);
  axis_d2_.resize(std::size_t(n.x + n.y + n.z));
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n[a]; ++i) {
      const int x = box_.lo[a] + i;
      axis_d2_[std::size_t(axis_off_[a] + i)] = axisGap2(c[a], x, x, eps);
    }
}

}  // namespace ml::hashed
