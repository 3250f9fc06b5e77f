#include "host/hashed/OctreeCellView.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "host/hashed/SceneOctree.hpp"
#include "host/util/IdColour.hpp"
#include "host/util/SplitMix64.hpp"

namespace ml::hashed {
namespace {

// A node key (depth and coordinates) mixed down to 18 bits.
std::uint32_t mixedKey(const LinklessOctree::Cell& cell) {
  return std::uint32_t(SplitMix64::mix(nodeKey(cell.depth, cell.coord) + SplitMix64::kGolden) >> 46);
}

}  // namespace

Rgb octreeCellColour(const LinklessOctree::Cell& cell) {
  using Kind = LinklessOctree::Cell::Kind;
  if (cell.kind == Kind::Outside) return {0.05f, 0.05f, 0.30f};
  const std::uint32_t h = mixedKey(cell);
  if (cell.kind == Kind::Filled) return idColour(h);
  const float grey = float(24u + h % 40u) / 255.0f;  // below idColour's levels (64 and up)
  return {grey, grey, grey};
}

std::vector<float> octreeCellViewRgba(const LinklessOctree& octree, const DebugViewInputs& frame) {
  std::vector<float> rgba(std::size_t(frame.width) * frame.height * 4, 0.0f);
  tbb::parallel_for(tbb::blocked_range<unsigned>(0, frame.height), [&](const tbb::blocked_range<unsigned>& rows) {
    for (unsigned y = rows.begin(); y < rows.end(); ++y)
      for (unsigned x = 0; x < frame.width; ++x) {
        float* p = &rgba[(std::size_t(y) * frame.width + x) * 4];
        p[3] = 1.0f;
        glm::vec3 world;
        if (!frame.worldAt(x, y, world)) continue;
        const Rgb c = octreeCellColour(octree.cellAt(world));
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
      }
  });
  return rgba;
}

}  // namespace ml::hashed
