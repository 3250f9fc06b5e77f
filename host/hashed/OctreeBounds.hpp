#pragma once
// The octree's place in the world (thesis §7.2.2) and the user parameters that
// fix it. Contract:
//  - The octree is a cube of side 2^depth * cell_size whose cells (the deepest
//    nodes, size `cell_size` = the thesis's minimal node size d) are addressed
//    by integer coordinates in [0, 2^depth)^3. A node at depth t has
//    coordinates in [0, 2^t)^3; its parent is coord >> 1.
//  - World -> cell mapping is ONE float expression, `(p - origin_f) * cell_scale`,
//    evaluated identically by the GLSL lookup, the CPU lookup and the builders
//    (which widen every light by `eps_cells` so that float rounding of that
//    expression can never put a point in a cell that misses its light).
//  - Parameters are validated here, before anything is allocated: a
//    non-positive node size, more than kMaxDepth layers or an estimated
//    footprint above the memory limit throw UserError naming the flag.
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/shared/gpu_types.h"
#include "host/util/ThesisSeed.hpp"

namespace ml::hashed {

// Coordinates are packed in 16 bits per axis in the hash entries, and 0xFFFF
// marks an empty slot: 2^15 cells per axis is the limit.
constexpr unsigned kMaxDepth = 15;

struct NodeSizeSpec {
  double value = 0.5;
  bool relative = true;  // value times the median light radius
};
// "0.5r" (relative to the median light radius) or "2.0" (world units).
// Throws UserError naming --node-size for anything else or for value <= 0.
NodeSizeSpec parseNodeSize(const std::string& text);

struct HashedConfig {
  std::string node_size = "0.5r";
  unsigned start_depth = 3;  // requested; clamped to depth - 1 (see OctreeBounds)
  bool geometry_mask = false;
  // Build refuses parameter sets whose estimated footprint exceeds this.
  std::size_t memory_limit = std::size_t(1) << 30;
  std::uint64_t seed = kThesisSeed;  // for random offset candidates
  // Hash tables get m >= slack * n entries: 1.0 is the thesis's sizing; a
  // dynamic update that forces a rehash rebuilds that table with
  // `rehash_slack` so that later inserts find empty slots more often.
  double table_slack = 1.0;
  // Offset entries per key of a built table. The thesis's 1/6 [LH06] fails
  // its first assignment for most tables above ~10k keys at these 1.01 n
  // tables, and each failure doubles the offset table and starts again (1M
  // lights, 0.5r: the deepest data table's doomed first try took 130-300 ms
  // on the build's serial path). 1/3 succeeds first time for nearly all of
  // them, for 0.4% more table bytes at 0.5r and 4% at 1r (docs/scaling.md,
  // "Hashed build at 1M lights, second pass").
  double table_sigma = 1.0 / 3.0;
  double rehash_slack = 2.0;
  // Offset entries per key of a rehashed table (the thesis's 1/6 for static
  // tables): smaller offset groups re-offset into free slots far more often,
  // so later inserts rarely need another rehash. Costs 4 bytes per 2 keys.
  double rehash_sigma = 0.5;
  // Extra room around the lights' bounds, as a fraction of their extent, so
  // moving lights leave the octree (forcing a full rebuild) less often.
  // Empty space costs nothing but, at worst, one more layer.
  double bounds_padding = 0.05;
  // An update touching more than this fraction of the lights rebuilds
  // instead (same result, less work).
  double max_incremental_fraction = 0.5;
  // Geometry mask: cells within this many cell sizes of a triangle count as
  // containing geometry, so deferred shading's reconstructed positions (off
  // the surface by depth-buffer rounding) still land in a kept cell.
  // With the mask a light is listed for a cell only when it reaches the
  // geometry inside the cell (beyond the thesis: tighter lists).
  double geometry_margin_cells = 0.01;
  // Octant masks on the deepest leaves' index entries (OctantMask.hpp): the
  // lookup skips lights that miss the point's octant of its cell. Off: every
  // entry has all 8 bits (the thesis's lists), for comparison.
  bool octant_masks = true;
};

struct OctreeBounds {
  glm::dvec3 origin{0.0};
  double cell_size = 1.0;   // d: edge of the deepest nodes, world units
  unsigned depth = 1;       // L: number of layers below the root; 2^L cells per axis
  unsigned start_depth = 0; // effective d_s in [0, depth - 1]
  glm::vec3 origin_f{0.0f}; // the float copies the lookups use
  float cell_scale = 1.0f;  // float(1 / cell_size)
  double eps_cells = 1e-4;  // conservative widening of light spheres, in cells

  std::uint32_t cellsPerAxis() const { return 1u << depth; }
  double side() const { return cell_size * double(cellsPerAxis()); }
  // The mirrored float expression; may be outside [0, 2^depth).
  glm::vec3 cellCoordF(const glm::vec3& p) const { return (p - origin_f) * cell_scale; }
  // Light centre and radius in cell units (double, for overlap tests).
  glm::dvec3 toCells(const glm::dvec3& p) const { return (p - glm::dvec3(origin_f)) * double(cell_scale); }
  double radiusCells(double r) const { return r * double(cell_scale); }
  bool operator==(const OctreeBounds& o) const {
    return origin_f == o.origin_f && cell_scale == o.cell_scale && depth == o.depth && start_depth == o.start_depth;
  }
};

// Resolves the node size (relative sizes use the median radius in `lights`)
// and the cube around the lights' spheres (centred, widened by a small
// rounding offset, the thesis's c, plus `padding` of the extent), then checks
// the estimated memory against `memory_limit`. Empty light sets get a unit
// octree of depth 1 that every lookup reads as empty.
OctreeBounds computeBounds(const std::vector<gpu::PointLight>& lights, const HashedConfig& config);

// Same, for a caller-chosen box (e.g. a level's extent) and absolute node size.
OctreeBounds boundsForBox(const glm::dvec3& box_min, const glm::dvec3& box_max, double node_size,
                          unsigned start_depth, const std::string& flag = "--node-size");

// Estimated peak bytes of a build. Without a geometry mask every (light,
// cell) pair of the lights' cell boxes may end in the scene octree and the
// index list: ~16 bytes each. With one (`geometry_mask`) only the pairs in
// cells with geometry do, and their count is known once the light octrees
// are built: this estimate then covers the light octrees (a record each and
// about a node byte per pair), and checkLitMemory() the rest. Throws
// UserError naming --node-size when it exceeds `limit`.
std::size_t estimateBuildBytes(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b,
                               bool geometry_mask = false);
void checkMemory(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b, std::size_t limit,
                 const std::string& node_size_text, bool geometry_mask = false);
// With a geometry mask, after the light octrees: the build's peak from the
// lights' `lit_pairs` (their filled cells, summed), the pairs that reach the
// scene octree.
std::size_t estimateLitBytes(std::size_t lights, std::size_t lit_pairs);
void checkLitMemory(std::size_t lights, std::size_t lit_pairs, std::size_t limit, const std::string& node_size_text);

// True when every light's sphere (widened by eps) lies inside the octree.
bool lightsInside(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b);

// The inclusive cell box [lo, hi] a light's sphere touches, clamped to the octree.
struct CellBox {
  glm::ivec3 lo{0}, hi{-1};
  bool empty() const { return hi.x < lo.x || hi.y < lo.y || hi.z < lo.z; }
};
CellBox lightCellBox(const gpu::PointLight& light, const OctreeBounds& b);

// Squared distance from the light centre `c` (cell units) to the cell box
// [lo, hi + 1) widened by eps, compared with r^2: the node-light overlap test
// of thesis Listing 7 (as its prose states it: closest point closer than r).
bool sphereOverlapsCells(const glm::dvec3& c, double r, const glm::ivec3& lo, const glm::ivec3& hi, double eps);
// Its term for one axis: the squared distance from `c` to [lo - eps, hi + 1 + eps]
// (the test sums the three terms in axis order).
inline double axisGap2(double c, int lo, int hi, double eps) {
  const double mn = double(lo) - eps, mx = double(hi) + 1.0 + eps;
  const double v = c < mn ? mn - c : (c > mx ? c - mx : 0.0);
  return v * v;
}

}  // namespace ml::hashed
