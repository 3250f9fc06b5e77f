#pragma once
// Tile culling math shared by the C++ reference culler: the same tests as
// kernels/tiled/tiled_light_culling.cl, written once for the host so tests can hold
// the kernel to them exactly. Depth modes: none (screen-space only, the main
// thesis's tiled variant), min/max depth bounds, 2.5D depth mask (32 bins).
#include <cstdint>
#include <string>

#include "host/shared/gpu_types.h"

namespace ml {

// Largest tile edge the culler takes (its per-tile work-group and local
// arrays); the tiled descriptor's `tile` range reads it.
constexpr unsigned kMaxTileSize = 256;

enum class TileDepthMode : int { None = 0, MinMax = 1, Mask = 2 };
TileDepthMode parseTileDepthMode(const std::string& s);  // UserError naming --tile-depth
const char* tileDepthModeName(TileDepthMode m);

struct TileGrid {
  unsigned tile_size = 16;
  unsigned width = 0, height = 0;
  unsigned tilesX() const { return (width + tile_size - 1) / tile_size; }
  unsigned tilesY() const { return (height + tile_size - 1) / tile_size; }
  unsigned count() const { return tilesX() * tilesY(); }
};

// Per-tile depth record, as the kernel writes it.
struct TileDepth {
  float zmin_widened, zmax_widened, zmin, inv_range;
  std::uint32_t mask;
  bool empty() const { return zmin_widened > zmax_widened; }
};

constexpr float kTileDepthEps = 1e-4f;

// depth: window-space floats (host/shared/depth_convention.h), row 0 at the bottom.
TileDepth tileDepth(const float* depth, const gpu::CameraParams& cam, const TileGrid& g, unsigned tx, unsigned ty,
                    TileDepthMode mode);

struct LightTileRect {
  float cx, cy, cz, r;  // view-space centre, radius
  int tx0, ty0, tx1, ty1;
  bool empty() const { return tx0 > tx1 || ty0 > ty1; }
};
LightTileRect lightTileRect(const gpu::PointLight& l, const gpu::CameraParams& cam, const TileGrid& g);
bool lightHitsTile(const LightTileRect& lr, unsigned tx, unsigned ty, const gpu::CameraParams& cam,
                   const TileGrid& g, const TileDepth& td, TileDepthMode mode);

}  // namespace ml
