#pragma once
// Which octree nodes contain geometry (future work A of the thesis,
// Tegelaers, KU Leuven, §8.2): the scene's triangles voxelised at the
// octree's cell resolution, and the same occupancy for every shallower depth. Contract:
//  - A cell counts as containing geometry when a triangle touches the cell's
//    box widened by `margin_cells` on every side (triangle/box separating-axis
//    test), so points computed on or near a surface (interpolated in forward,
//    reconstructed from depth in deferred) always fall in a marked cell.
//  - has(t, c) is exact for every depth t <= bounds.depth; cells outside the
//    octree never contain geometry.
//  - Cell c's geometry box bounds the geometry inside it (each triangle clipped
//    to the widened cell, the clipped polygons' bounds united), in cell
//    units: a floor cell's box is a thin slab. Lights that miss it cannot
//    light any surface point in the cell (see LightOctreeBuilder).
//  - octantBoxes(c): the same per octant of the cell (k = x + 2y + 4z; each
//    triangle clipped to the octant widened by the margin): a surface point
//    in the cell lies in its octant's box, so a light that misses every
//    octant's box cannot reach one. Geometry finer than the cell (a floor
//    meeting a wall, a slanted panel) so keeps lights off cells whose whole
//    box they would reach.
//  - The geometry box holds every octant box of c (exactly: it is united with
//    them), so a sphere that misses or holds it misses or holds them all.
#include <glm/glm.hpp>

#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/hashed/OctreeBounds.hpp"
#include "host/scene/Scene.hpp"

namespace ml::hashed {

// std::popcount: without -mpopcnt (the x86-64 baseline) GCC calls libgcc
// for it, which took 2.6% of a 1M-light build; the same count inline.
inline std::size_t bitCount(std::uint64_t v) {
#if defined(__POPCNT__) || !defined(__x86_64__)
  return std::size_t(std::popcount(v));
#else
  v -= (v >> 1) & 0x5555555555555555ull;
  v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
  v = (v + (v >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return std::size_t((v * 0x0101010101010101ull) >> 56);
#endif
}

class GeometryMask {
 public:
  // Thrown when the builder's buffers, counted as they grow, would pass
  // `byte_limit`: a refused build has allocated about that much at most. The
  // memory is counted, not estimated beforehand, because no cheap estimate is
  // close: per-triangle cell counts overrate the distinct cells of a mesh 3x
  // (adjacent triangles share cells), which refused builds that fit.
  struct OverLimit : std::runtime_error {
    std::size_t bytes;
    explicit OverLimit(std::size_t b) : std::runtime_error("geometry mask over its memory limit"), bytes(b) {}
  };
  GeometryMask(const Scene& scene, const OctreeBounds& bounds, double margin_cells,
               std::size_t byte_limit = std::numeric_limits<std::size_t>::max());
  // The most bytes the build held at once (its buffers, then the final mask).
  std::size_t peakBytes() const { return peak_bytes_; }

  bool has(unsigned depth, const glm::uvec3& c) const;
  struct Box {
    glm::dvec3 lo, hi;
  };
  // Per octant, in floats rounded outwards; an octant without geometry has lo > hi.
  struct OctantBoxes {
    std::array<glm::vec3, 8> lo, hi;
    OctantBoxes() {
      lo.fill(glm::vec3(std::numeric_limits<float>::max()));
      hi.fill(glm::vec3(-std::numeric_limits<float>::max()));
    }
    bool empty(unsigned k) const { return lo[k].x > hi[k].x; }
  };
  // The cell's octant boxes, and its geometry box in `cell_box`; null
  // (and `cell_box` untouched) when the cell holds no geometry.
  const OctantBoxes* octantBoxes(const glm::uvec3& cell, const Box*& cell_box) const;
  // The cells with geometry in the row (y, z) with x_lo <= x <= x_hi, in x
  // order, as indices [first, last) for cellX()/cellBox()/cellOctants(): one
  // search per row instead of one per cell (the light octrees ask for every
  // cell of a light's box, and most of their build went to those searches).
  std::pair<std::size_t, std::size_t> rowCells(unsigned y, unsigned z, unsigned x_lo, unsigned x_hi) const;
  unsigned cellX(std::size_t i) const { return unsigned(cell_keys_[i] & 0xFFFF); }
  const Box& cellBox(std::size_t i) const { return cell_boxes_[i]; }
  const OctantBoxes& cellOctants(std::size_t i) const { return cell_octants_[i]; }
  std::size_t cellCount() const { return cell_count_; }

 private:
  void setCells(std::vector<std::uint64_t> keys);
  struct CellGeometry {
    Box box;
    OctantBoxes oct;
  };
  // The final arrays from runs of (cell, geometry) pairs, each sorted by
  // cell without repeats (a cell in several runs is united).
  void setBoxes(const std::vector<std::vector<std::pair<std::uint64_t, CellGeometry>>*>& runs,
                std::size_t byte_limit);
  void setRowIndex();
  void setRanks();
  // Cells of the deepest level before cell index i (x + side (y + side z)):
  // where i lies in the sorted arrays. Only with dense_rank_.
  std::size_t rank(std::uint64_t i) const {
    const std::uint64_t below = (std::uint64_t(1) << (i & 63)) - 1;
    return dense_rank_[i >> 6] + bitCount(dense_[depth_][i >> 6] & below);
  }
  bool indexOf(const glm::uvec3& c, std::size_t& at) const;
  unsigned depth_;
  // Per depth: a bitset when the depth's full grid is small, else the sorted
  // packed coordinates of the occupied nodes.
  std::vector<std::vector<std::uint64_t>> dense_;
  std::vector<std::vector<std::uint64_t>> sparse_;
  // Deepest level: sorted keys with their geometry boxes, plus a dense
  // index (key -> position + 1) when the level is small enough.
  std::vector<std::uint64_t> cell_keys_;
  std::vector<Box> cell_boxes_;
  std::vector<OctantBoxes> cell_octants_;
  std::vector<std::uint32_t> dense_index_;
  // Where each row (y, z) of the deepest level starts in cell_keys_ (side^2 + 1
  // entries), when the level is small enough: rowCells() without a search
  // over every key.
  std::vector<std::uint32_t> row_start_;
  // When the deepest level has a bitset (dense_): per 64-bit word, the cells
  // before it (rowCells() and indexOf() by counting bits instead of
  // searching: a tenth of a 1M-light build went to those searches).
  std::vector<std::uint32_t> dense_rank_;
  std::size_t cell_count_ = 0;
  std::size_t peak_bytes_ = 0;
};

inline std::uint64_t packCoord(const glm::uvec3& c) {
  return std::uint64_t(c.x) | (std::uint64_t(c.y) << 16) | (std::uint64_t(c.z) << 32);
}
inline glm::uvec3 unpackCoord(std::uint64_t k) {
  return {std::uint32_t(k & 0xFFFF), std::uint32_t((k >> 16) & 0xFFFF), std::uint32_t((k >> 32) & 0xFFFF)};
}

}  // namespace ml::hashed
