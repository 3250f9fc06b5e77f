#include "host/hashed/GeometryMask.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

namespace ml::hashed {
namespace {

// 8^9 bits = 16 MiB (and 8 MiB of ranks): the deepest level of a 0.5r
// octree at 1M lights is 9, and its bitset answers rowCells()/indexOf() by
// counting bits instead of two binary searches per row (a tenth of that
// build's time went to them).
constexpr unsigned kDenseMaxDepth = 9;
constexpr unsigned kDenseIndexMaxDepth = 7;  // 8^7 entries = 8 MiB
constexpr unsigned kRowIndexMaxDepth = 11;   // 4^11 rows = 16 MiB
// Cells: a clipped part this far beyond a face misses it whatever the
// rounding (coordinates are below 2^16 cells, rounding errors below 1e-11).
constexpr double kClearlyOutside = 1e-9;
// A builder thread merges its (cell, box) pairs by cell whenever its buffer
// reaches twice what it held after the last merge, and at least this many.
constexpr std::size_t kMergeBatch = std::size_t(1) << 16;

float floatDown(double x) {
  float f = float(x);
  if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::max());
  return f;
}
float floatUp(double x) {
  float f = float(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::max());
  return f;
}

void unite(GeometryMask::Box& a, const GeometryMask::Box& b) {
  a.lo = glm::min(a.lo, b.lo);
  a.hi = glm::max(a.hi, b.hi);
}

template <class CellGeometry>
void unite(CellGeometry& a, const CellGeometry& b) {
  unite(a.box, b.box);
  for (unsigned k = 0; k < 8; ++k) {
    a.oct.lo[k] = glm::min(a.oct.lo[k], b.oct.lo[k]);
    a.oct.hi[k] = glm::max(a.oct.hi[k], b.oct.hi[k]);
  }
}

// Sorts by cell and unites the boxes of equal cells, in place. The sort
// orders (cell, position) pairs and then moves each ~250-byte pair once
// along the permutation's cycles: sorting the pairs themselves moved them
// O(log n) times and was most of the mask's serial time.
template <class CellGeometry>
void mergeByCell(std::vector<std::pair<std::uint64_t, CellGeometry>>& v) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) order[i] = {v[i].first, std::uint32_t(i)};
  std::sort(order.begin(), order.end());
  // v[i] = old v[order[i].second]; a moved slot's source is set to itself.
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (order[i].second == i) continue;
    auto held = std::move(v[i]);
    std::size_t j = i;
    while (order[j].second != i) {
      const std::size_t from = order[j].second;
      v[j] = std::move(v[from]);
      order[j].second = std::uint32_t(j);
      j = from;
    }
    v[j] = std::move(held);
    order[j].second = std::uint32_t(j);
  }
  std::size_t w = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (w > 0 && v[w - 1].first == v[i].first) {
      unite(v[w - 1].second, v[i].second);
    } else {
      v[w++] = v[i];
    }
  }
  v.resize(w);
}

// Appends a (cell, geometry) pair, or unites it with one of the last few
// pairs when that has the same cell: a mesh's consecutive triangles are
// neighbours, so this merges most pairs before mergeByCell() has to sort
// them (sorting the ~250-byte pairs was the builder's largest cost).
template <class CellGeometry>
void addCell(std::vector<std::pair<std::uint64_t, CellGeometry>>& out, std::uint64_t key, const CellGeometry& g) {
  constexpr std::size_t kRecent = 8;
  for (std::size_t i = out.size(); i > 0 && i + kRecent > out.size(); --i)
    if (out[i - 1].first == key) {
      unite(out[i - 1].second, g);
      return;
    }
  out.push_back({key, g});
}

// A convex polygon being clipped (a triangle cut by up to 9 planes).
struct Polygon {
  glm::dvec3 p[12];
  int n = 0;
};

// Sutherland-Hodgman against one plane: keeps p[a] >= bound, or p[a] <=
// bound when `upper`.
void clipPlane(Polygon& poly, int a, bool upper, double bound) {
  auto inside = [&](const glm::dvec3& p) { return upper ? p[a] <= bound : p[a] >= bound; };
  // Most cuts keep or drop the whole polygon (an octant's part of a floor):
  // what the loop below would also give, without copying.
  int kept = 0;
  for (int i = 0; i < poly.n; ++i) kept += inside(poly.p[i]);
  if (kept == poly.n) return;
  if (kept == 0) {
    poly.n = 0;
    return;
  }
  glm::dvec3 next[12];
  int m = 0;
  for (int i = 0; i < poly.n; ++i) {
    const glm::dvec3& p = poly.p[i];
    const glm::dvec3& q = poly.p[(i + 1) % poly.n];
    const bool pin = inside(p), qin = inside(q);
    if (pin) next[m++] = p;
    if (pin != qin && m < 12) {
      const double t = (bound - p[a]) / (q[a] - p[a]);
      glm::dvec3 x = p + t * (q - p);
      x[a] = bound;
      next[m++] = x;
    }
  }
  poly.n = m;
  for (int i = 0; i < m; ++i) poly.p[i] = next[i];
}

bool polygonBounds(const Polygon& poly, GeometryMask::Box& out) {
  if (poly.n == 0) return false;
  out.lo = out.hi = poly.p[0];
  for (int i = 1; i < poly.n; ++i) {
    out.lo = glm::min(out.lo, poly.p[i]);
    out.hi = glm::max(out.hi, poly.p[i]);
  }
  return true;
}

Polygon trianglePolygon(const glm::dvec3 v[3]) {
  Polygon poly;
  poly.n = 3;
  for (int i = 0; i < 3; ++i) poly.p[i] = v[i];
  return poly;
}

// Triangle v[0..2] clipped to the box [lo, hi]; empty when nothing is left.
Polygon clippedTriangle(const glm::dvec3 v[3], const glm::dvec3& lo, const glm::dvec3& hi) {
  Polygon poly = trianglePolygon(v);
  for (int plane = 0; plane < 6 && poly.n > 0; ++plane) {
    const int a = plane / 2;
    const bool upper = plane & 1;
    clipPlane(poly, a, upper, upper ? hi[a] : lo[a]);
  }
  return poly;
}

// The box-axis part of triangleBoxOverlap() on the triangle's bounds (the
// same comparisons: subtracting the centre keeps the order of the vertices),
// so that cells and octants the bounds miss skip the other 10 axes.
bool boundsOverlap(const glm::dvec3& tlo, const glm::dvec3& thi, const glm::dvec3& centre, double h) {
  for (int a = 0; a < 3; ++a)
    if (tlo[a] - centre[a] > h || thi[a] - centre[a] < -h) return false;
  return true;
}

// Akenine-Moller's separating-axis test of a triangle against the box
// centred at the origin with half size h (same on every axis).
bool triangleBoxOverlap(glm::dvec3 v0, glm::dvec3 v1, glm::dvec3 v2, double h) {
  const glm::dvec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
  const glm::dvec3 v[3] = {v0, v1, v2};
  // 9 edge x box-axis directions.
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) {
      glm::dvec3 axis(0.0);
      axis[a] = 1.0;
      const glm::dvec3 n = glm::cross(axis, e[i]);
      const double p0 = glm::dot(n, v[0]), p1 = glm::dot(n, v[1]), p2 = glm::dot(n, v[2]);
      const double rad = h * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
      if (std::min({p0, p1, p2}) > rad || std::max({p0, p1, p2}) < -rad) return false;
    }
  // Box axes.
  for (int a = 0; a < 3; ++a)
    if (std::min({v0[a], v1[a], v2[a]}) > h || std::max({v0[a], v1[a], v2[a]}) < -h) return false;
  // Triangle plane.
  const glm::dvec3 n = glm::cross(e[0], e[1]);
  const double d = glm::dot(n, v0);
  const double rad = h * (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
  return std::fabs(d) <= rad;
}

}  // namespace

bool GeometryMask::indexOf(const glm::uvec3& c, std::size_t& at) const {
  const std::uint64_t side = std::uint64_t(1) << depth_;
  if (c.x >= side || c.y >= side || c.z >= side) return false;
  if (!dense_index_.empty()) {
    const std::uint32_t i = dense_index_[c.x + side * (c.y + side * c.z)];
    if (i == 0) return false;
    at = i - 1;
    return true;
  }
  if (!dense_rank_.empty()) {
    const std::uint64_t i = c.x + side * (c.y + side * c.z);
    if (!((dense_[depth_][i >> 6] >> (i & 63)) & 1u)) return false;
    at = rank(i);
    return true;
  }
  const auto it = std::lower_bound(cell_keys_.begin(), cell_keys_.end(), packCoord(c));
  if (it == cell_keys_.end() || *it != packCoord(c)) return false;
  at = std::size_t(it - cell_keys_.begin());
  return true;
}

const GeometryMask::OctantBoxes* GeometryMask::octantBoxes(const glm::uvec3& c, const Box*& cell_box) const {
  std::size_t at;
  if (!indexOf(c, at)) return nullptr;
  cell_box = &cell_boxes_[at];
  return &cell_octants_[at];
}

std::pair<std::size_t, std::size_t> GeometryMask::rowCells(unsigned y, unsigned z, unsigned x_lo,
                                                           unsigned x_hi) const {
  const std::uint64_t side = std::uint64_t(1) << depth_;
  if (y >= side || z >= side || x_lo > x_hi) return {0, 0};
  // Keys order by z, then y, then x: a row's cells are consecutive.
  if (!dense_rank_.empty()) {  // their positions: the cells before them
    const std::uint64_t row = y + side * z, base = side * row;
    if (row_start_[row] == row_start_[row + 1]) return {row_start_[row], row_start_[row]};  // most rows
    const std::uint64_t x_end = std::min<std::uint64_t>(x_hi, side - 1) + 1;
    return {rank(base + std::min<std::uint64_t>(x_lo, side)), rank(base + x_end)};
  }
  const std::uint64_t lo = packCoord({x_lo, y, z}), hi = packCoord({std::min<std::uint64_t>(x_hi, side - 1), y, z});
  auto begin = cell_keys_.begin(), end = cell_keys_.end();
  if (!row_start_.empty()) {
    const std::uint64_t row = y + side * z;
    end = begin + row_start_[row + 1];
    begin += row_start_[row];
  }
  const auto first = std::lower_bound(begin, end, lo);
  const auto last = std::upper_bound(first, end, hi);
  return {std::size_t(first - cell_keys_.begin()), std::size_t(last - cell_keys_.begin())};
}

namespace {

// The bytes the builder holds, shared by its threads: each reports what its
// buffer's capacity grew by, and the first to pass the limit stops the build
// (tbb::parallel_for passes the exception on to the caller).
class HeldBytes {
 public:
  explicit HeldBytes(std::size_t limit) : limit_(limit) {}
  void grew(std::size_t before, std::size_t after) {
    if (after <= before) return;
    add(after - before);
  }
  void add(std::size_t bytes) {
    const std::size_t now = held_.fetch_add(bytes) + bytes;
    std::size_t p = peak_.load();
    while (now > p && !peak_.compare_exchange_weak(p, now)) {
    }
    if (now > limit_) throw GeometryMask::OverLimit(now);
  }
  std::size_t peak() const { return peak_.load(); }

 private:
  std::size_t limit_;
  std::atomic<std::size_t> held_{0}, peak_{0};
};

}  // namespace

namespace {

// One triangle in cell units, with its bounds, as the voxeliser tests it.
struct TriangleInCells {
  const glm::dvec3* v;      // 3 vertices
  glm::dvec3 tlo, thi;      // bounds
  glm::dvec3 lo, hi;        // bounds widened by the margin
  // Whether it touches the box centred at `centre` with half size h.
  bool touches(const glm::dvec3& centre, double h) const {
    return boundsOverlap(tlo, thi, centre, h) && triangleBoxOverlap(v[0] - centre, v[1] - centre, v[2] - centre, h);
  }
  // Where clipping lost a part that the separating-axis test says touches
  // (rounding): the box and the widened bounds' overlap stands in.
  GeometryMask::Box fallback(const glm::dvec3& centre, double h) const {
    return {glm::max(lo, centre - h), glm::min(hi, centre + h)};
  }
};

// The triangle's part in the widened cell centred at `centre` (half size h):
// the triangle itself when it lies inside, else clipped to the box.
Polygon cellPart(const TriangleInCells& tri, const glm::dvec3& centre, double h) {
  if (glm::all(glm::greaterThanEqual(tri.tlo, centre - h)) && glm::all(glm::lessThanEqual(tri.thi, centre + h)))
    return trianglePolygon(tri.v);
  return clippedTriangle(tri.v, centre - h, centre + h);
}

// The bounds of the triangle's part in octant k's widened box (centre oc,
// half size h) from its part in the widened cell: the octant's box lies
// inside the cell's, so only its 3 inner faces cut (3 planes per octant
// instead of 6, and the separating-axis test only where nothing is left).
// `cell_bounds`: in_cell's bounds (when it is not empty). A part clearly
// beyond an inner face (by more than rounding) misses the octant: no
// clipping, and no separating-axis test either (half of a floor cell's
// octants; that test was most of the mask's time).
bool octantPart(const TriangleInCells& tri, const Polygon& in_cell, const GeometryMask::Box& cell_bounds,
                const glm::dvec3& oc, double h, unsigned k, GeometryMask::Box& out) {
  if (in_cell.n > 0) {
    for (int a = 0; a < 3; ++a) {
      const bool high = (k >> a) & 1u;
      if (high ? cell_bounds.hi[a] < oc[a] - h - kClearlyOutside : cell_bounds.lo[a] > oc[a] + h + kClearlyOutside)
        return false;
    }
    Polygon q = in_cell;
    for (int a = 0; a < 3 && q.n > 0; ++a) {
      const bool high = (k >> a) & 1u;  // the octant's upper half on axis a: its low face cuts
      clipPlane(q, a, !high, high ? oc[a] - h : oc[a] + h);
    }
    if (polygonBounds(q, out)) return true;
  }
  if (!tri.touches(oc, h)) return false;
  out = tri.fallback(oc, h);
  return true;
}

// One cell's geometry: false when the triangle misses the widened cell.
template <class CellGeometry>
bool cellGeometry(const TriangleInCells& tri, const glm::dvec3& centre, double margin, CellGeometry& g) {
  const double hc = 0.5 + margin, ho = 0.25 + margin;
  if (!tri.touches(centre, hc)) return false;
  const Polygon in_cell = cellPart(tri, centre, hc);
  if (!polygonBounds(in_cell, g.box)) g.box = tri.fallback(centre, hc);
  const GeometryMask::Box cell_bounds = g.box;
  g.box.lo -= margin;
  g.box.hi += margin;
  for (unsigned k = 0; k < 8; ++k) {
    const glm::dvec3 oc = centre + glm::dvec3((k & 1) ? 0.25 : -0.25, (k & 2) ? 0.25 : -0.25, (k & 4) ? 0.25 : -0.25);
    GeometryMask::Box ob;
    if (!octantPart(tri, in_cell, cell_bounds, oc, ho, k, ob)) continue;
    for (int a = 0; a < 3; ++a) {
      g.oct.lo[k][a] = floatDown(ob.lo[a] - margin);
      g.oct.hi[k][a] = floatUp(ob.hi[a] + margin);
    }
  }
  return true;
}

}  // namespace

// One triangle's (cell, geometry) pairs: every cell whose box widened by
// `margin` the triangle touches, with the bounds of the triangle's part in the
// widened cell and in each widened octant, each widened by the margin again
// (so points off the surface by rounding stay inside). `v` in cells; `n`
// cells per axis.
template <class CellGeometry>
void voxelizeTriangle(const glm::dvec3 v[3], double margin, double n,
                      std::vector<std::pair<std::uint64_t, CellGeometry>>& out, HeldBytes& held) {
  TriangleInCells tri{v, glm::min(v[0], glm::min(v[1], v[2])), glm::max(v[0], glm::max(v[1], v[2])), {}, {}};
  tri.lo = tri.tlo - margin;
  tri.hi = tri.thi + margin;
  const glm::dvec3 &lo = tri.lo, &hi = tri.hi;
  if (hi.x < 0 || hi.y < 0 || hi.z < 0 || lo.x >= n || lo.y >= n || lo.z >= n) return;
  const glm::ivec3 clo(glm::clamp(glm::floor(lo), glm::dvec3(0.0), glm::dvec3(n - 1)));
  const glm::ivec3 chi(glm::clamp(glm::floor(hi), glm::dvec3(0.0), glm::dvec3(n - 1)));
  for (int z = clo.z; z <= chi.z; ++z)
    for (int y = clo.y; y <= chi.y; ++y)
      for (int x = clo.x; x <= chi.x; ++x) {
        CellGeometry g;
        if (!cellGeometry(tri, glm::dvec3(x + 0.5, y + 0.5, z + 0.5), margin, g)) continue;
        const std::size_t capacity = out.capacity();
        addCell(out, packCoord(glm::uvec3(x, y, z)), g);
        // Counted at every growth: one large triangle can make millions of pairs.
        held.grew(capacity * sizeof(out[0]), out.capacity() * sizeof(out[0]));
      }
}

GeometryMask::GeometryMask(const Scene& scene, const OctreeBounds& b, double margin_cells, std::size_t byte_limit)
    : depth_(b.depth) {
  const double n = double(b.cellsPerAxis());
  const double margin = std::max(margin_cells, 0.0) + b.eps_cells;
  using Pair = std::pair<std::uint64_t, CellGeometry>;
  struct Local {
    std::vector<Pair> pairs;
    std::size_t merge_at = kMergeBatch;
  };
  tbb::enumerable_thread_specific<Local> local;
  HeldBytes held(byte_limit);
  const std::size_t tris = scene.indices.size() / 3;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris, 8), [&](const auto& range) {
    Local& loc = local.local();
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k) v[k] = b.toCells(glm::dvec3(scene.vertices[scene.indices[3 * t + k]].position));
      voxelizeTriangle(v, margin, n, loc.pairs, held);
      // Many small triangles share cells: merging keeps the buffer near the
      // distinct cells' size instead of the (triangle, cell) pairs'.
      if (loc.pairs.size() >= loc.merge_at) {
        mergeByCell(loc.pairs);
        loc.merge_at = std::max(kMergeBatch, 2 * loc.pairs.size());
      }
    }
  });
  // Each thread's pairs sorted and united in parallel, then merged run by
  // run straight into the final arrays: gathering them into one vector and
  // sorting that again was a serial third of the mask's time at 1M lights.
  std::vector<std::vector<Pair>*> runs;
  for (auto& l : local) runs.push_back(&l.pairs);
  tbb::parallel_for(std::size_t(0), runs.size(), [&](std::size_t i) { mergeByCell(*runs[i]); });
  setBoxes(runs, byte_limit);
  peak_bytes_ = std::max(held.peak(), peak_bytes_);
}

void GeometryMask::setBoxes(const std::vector<std::vector<std::pair<std::uint64_t, CellGeometry>>*>& runs,
                            std::size_t byte_limit) {
  // The final arrays beside the runs (freed after), and the indexes.
  std::size_t total = 0;
  peak_bytes_ = 0;
  for (const auto* r : runs) {
    total += r->size();
    peak_bytes_ += r->capacity() * sizeof((*r)[0]);
  }
  const std::uint64_t side = std::uint64_t(1) << depth_;
  peak_bytes_ += total * (sizeof(std::uint64_t) + sizeof(Box) + sizeof(OctantBoxes)) +
                 (depth_ <= kDenseIndexMaxDepth ? side * side * side * sizeof(std::uint32_t) : 0) +
                 (depth_ <= kRowIndexMaxDepth ? side * side * sizeof(std::uint32_t) : 0) +
                 (depth_ <= kDenseMaxDepth ? side * side * side / 8 * 3 / 2 : 0);  // bits and ranks
  if (peak_bytes_ > byte_limit) throw OverLimit(peak_bytes_);
  cell_keys_.clear();
  cell_boxes_.clear();
  cell_octants_.clear();
  cell_keys_.reserve(total);
  cell_boxes_.reserve(total);
  cell_octants_.reserve(total);
  std::vector<std::size_t> at(runs.size(), 0);
  constexpr std::uint64_t kNone = ~std::uint64_t(0);  // keys use 48 bits
  for (;;) {
    // The least key at the runs' heads; every run holding it adds to the cell.
    std::uint64_t key = kNone;
    for (std::size_t i = 0; i < runs.size(); ++i)
      if (at[i] < runs[i]->size()) key = std::min(key, (*runs[i])[at[i]].first);
    if (key == kNone) break;
    CellGeometry g;
    bool first = true;
    for (std::size_t i = 0; i < runs.size(); ++i)
      if (at[i] < runs[i]->size() && (*runs[i])[at[i]].first == key) {
        if (first) g = (*runs[i])[at[i]].second;
        else unite(g, (*runs[i])[at[i]].second);
        first = false;
        ++at[i];
      }
    cell_keys_.push_back(key);
    Box box = g.box;  // holds the octant boxes (floats rounded outwards; a clip's fallback)
    for (unsigned o = 0; o < 8; ++o)
      if (!g.oct.empty(o)) unite(box, {glm::dvec3(g.oct.lo[o]), glm::dvec3(g.oct.hi[o])});
    cell_boxes_.push_back(box);
    cell_octants_.push_back(g.oct);
  }
  if (depth_ <= kDenseIndexMaxDepth) {
    dense_index_.assign(side * side * side, 0);
    for (std::size_t i = 0; i < cell_keys_.size(); ++i) {
      const glm::uvec3 c = unpackCoord(cell_keys_[i]);
      dense_index_[c.x + side * (c.y + side * c.z)] = std::uint32_t(i + 1);
    }
  }
  setRowIndex();
  setCells(cell_keys_);
  setRanks();
}

void GeometryMask::setRanks() {
  dense_rank_.clear();
  if (depth_ > kDenseMaxDepth || row_start_.empty()) return;  // rowCells() reads both
  const auto& bits = dense_[depth_];
  dense_rank_.resize(bits.size());
  std::uint32_t n = 0;
  for (std::size_t w = 0; w < bits.size(); ++w) {
    dense_rank_[w] = n;
    n += std::uint32_t(bitCount(bits[w]));
  }
}

void GeometryMask::setRowIndex() {
  row_start_.clear();
  if (depth_ > kRowIndexMaxDepth) return;
  const std::uint64_t side = std::uint64_t(1) << depth_;
  row_start_.assign(side * side + 1, 0);
  for (const std::uint64_t k : cell_keys_) {
    const glm::uvec3 c = unpackCoord(k);
    ++row_start_[c.y + side * c.z + 1];
  }
  for (std::size_t r = 1; r < row_start_.size(); ++r) row_start_[r] += row_start_[r - 1];
}

void GeometryMask::setCells(std::vector<std::uint64_t> keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  cell_count_ = keys.size();
  dense_.assign(depth_ + 1, {});
  sparse_.assign(depth_ + 1, {});
  for (int t = int(depth_); t >= 0; --t) {
    if (t < int(depth_)) {
      // Parents of the deeper level's nodes.
      std::vector<std::uint64_t> up;
      up.reserve(keys.size() / 4 + 1);
      for (auto k : keys) up.push_back(packCoord(unpackCoord(k) >> 1u));
      std::sort(up.begin(), up.end());
      up.erase(std::unique(up.begin(), up.end()), up.end());
      keys = std::move(up);
    }
    if (unsigned(t) <= kDenseMaxDepth) {
      const std::uint64_t side = std::uint64_t(1) << t;
      auto& bits = dense_[t];
      bits.assign((side * side * side + 63) / 64, 0);
      for (auto k : keys) {
        const glm::uvec3 c = unpackCoord(k);
        const std::uint64_t i = c.x + side * (c.y + side * c.z);
        bits[i >> 6] |= std::uint64_t(1) << (i & 63);
      }
    }
    if (unsigned(t) > kDenseMaxDepth) sparse_[t] = keys;
  }
}

bool GeometryMask::has(unsigned t, const glm::uvec3& c) const {
  const std::uint64_t side = std::uint64_t(1) << t;
  if (c.x >= side || c.y >= side || c.z >= side) return false;
  if (t <= kDenseMaxDepth) {
    const std::uint64_t i = c.x + side * (c.y + side * c.z);
    return (dense_[t][i >> 6] >> (i & 63)) & 1u;
  }
  if (t == depth_ && !row_start_.empty()) {  // the row's few cells, not all of them (the merge asks per node)
    const auto [first, last] = rowCells(c.y, c.z, c.x, c.x);
    return first != last;
  }
  const auto& v = sparse_[t];
  return std::binary_search(v.begin(), v.end(), packCoord(c));
}

}  // namespace ml::hashed
