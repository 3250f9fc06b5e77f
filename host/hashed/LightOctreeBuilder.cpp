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

// Bottom-up minimal octree of a grid whose cells are lit (kTestedIn), unlit
// (kOutside) or without geometry (kAssumedIn: may be taken either way).
struct GeometryTreeBuilder {
  const Grid& grid;
  unsigned depth;
  std::vector<LightNode>& out;
  enum class K { Empty, Full, Free, Mixed };

  K node(unsigned t, const glm::ivec3& coord) {
    const int shift = int(depth - t);
    const glm::ivec3 rlo = coord << shift, rhi = ((coord + 1) << shift) - 1;
    const glm::ivec3 glo = grid.lo, ghi = grid.lo + grid.n - 1;
    const glm::ivec3 ilo = glm::max(rlo, glo), ihi = glm::min(rhi, ghi);
    if (ilo.x > ihi.x || ilo.y > ihi.y || ilo.z > ihi.z) {
      out.push_back(LightNode::Empty);
      return K::Empty;
    }
    if (shift == 0) {
      const std::uint8_t v = grid.cells[grid.index(coord)];
      out.push_back(v == kTestedIn ? LightNode::Full : LightNode::Empty);
      return v == kTestedIn ? K::Full : v == kOutside ? K::Empty : K::Free;
    }
    const std::size_t at = out.size();
    out.push_back(LightNode::Branch);
    bool any_full = false, any_empty = false, mixed = false;
    for (int k = 0; k < 8; ++k) {
      const K r = node(t + 1, coord * 2 + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
      mixed = mixed || r == K::Mixed;
      any_full = any_full || r == K::Full;
      any_empty = any_empty || r == K::Empty;
    }
    if (mixed || (any_full && any_empty)) return K::Mixed;
    out.resize(at);
    out.push_back(any_full ? LightNode::Full : LightNode::Empty);
    return any_full ? K::Full : any_empty ? K::Empty : K::Free;
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

// Fewer lights are less work than waking the worker threads.
constexpr std::size_t kParallelOctreesMinLights = 256;

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
    GeometryTreeBuilder tb{g, b.depth, lo.nodes};
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

std::vector<LightOctree> buildLightOctrees(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b,
                                           const GeometryMask* geometry) {
  std::vector<LightOctree> out(lights.size());
  if (lights.size() < kParallelOctreesMinLights) {
    LightGridScratch s;
    for (std::size_t i = 0; i < lights.size(); ++i) out[i] = buildLightOctree(lights[i], std::uint32_t(i), b, s, geometry);
    return out;
  }
  tbb::enumerable_thread_specific<LightGridScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 16), [&](const auto& range) {
    LightGridScratch& s = scratch.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      out[i] = buildLightOctree(lights[i], std::uint32_t(i), b, s, geometry);
  });
  return out;
}

}  // namespace ml::hashed
