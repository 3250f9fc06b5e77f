#pragma once
// Plain C++ tile light culler, multi-threaded with TBB: the test reference for
// the OpenCL culler (same tests, TileGeometry.hpp) and its benchmark peer.
// Never used for rendering.
#include <cstdint>
#include <vector>

#include "host/tiled/TileGeometry.hpp"

namespace ml {

struct TileLists {
  std::vector<gpu::LightRange> grid;      // per tile
  std::vector<std::uint32_t> indices;     // concatenated, each tile's list ascending
};

// depth may be null when mode == None.
TileLists cullTilesReference(const std::vector<gpu::PointLight>& lights, const float* depth,
                             const gpu::CameraParams& cam, const TileGrid& g, TileDepthMode mode,
                             bool parallel = true);

}  // namespace ml
