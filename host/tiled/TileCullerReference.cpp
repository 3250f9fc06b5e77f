#include "host/tiled/TileCullerReference.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace ml {

TileLists cullTilesReference(const std::vector<gpu::PointLight>& lights, const float* depth,
                             const gpu::CameraParams& cam, const TileGrid& g, TileDepthMode mode, bool parallel) {
  const unsigned n_tiles = g.count();
  std::vector<TileDepth> tiles(n_tiles);
  std::vector<LightTileRect> rects(lights.size());
  auto for_range = [&](std::size_t n, auto&& body) {
    if (parallel) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
      });
    } else {
      for (std::size_t i = 0; i < n; ++i) body(i);
    }
  };
  for_range(n_tiles, [&](std::size_t t) {
    if (mode != TileDepthMode::None)
      tiles[t] = tileDepth(depth, cam, g, unsigned(t % g.tilesX()), unsigned(t / g.tilesX()), mode);
  });
  for_range(lights.size(), [&](std::size_t i) { rects[i] = lightTileRect(lights[i], cam, g); });
  // Light-centric like the kernel (each light walks its tile rectangle), in
  // parallel over lights; the merge then lists each tile's lights in light
  // order, which also makes the result deterministic.
  std::vector<std::vector<std::uint32_t>> hits(lights.size());
  for_range(lights.size(), [&](std::size_t i) {
    const auto& lr = rects[i];
    if (lr.empty()) return;
    for (int ty = lr.ty0; ty <= lr.ty1; ++ty)
      for (int tx = lr.tx0; tx <= lr.tx1; ++tx) {
        const unsigned t = unsigned(ty) * g.tilesX() + unsigned(tx);
        if (lightHitsTile(lr, unsigned(tx), unsigned(ty), cam, g, tiles[t], mode)) hits[i].push_back(t);
      }
  });
  std::vector<std::uint32_t> counts(n_tiles, 0);
  for (const auto& h : hits)
    for (std::uint32_t t : h) ++counts[t];
  TileLists out;
  out.grid.resize(n_tiles);
  std::uint32_t offset = 0;
  for (unsigned t = 0; t < n_tiles; ++t) {
    out.grid[t] = {offset, 0};
    offset += counts[t];
  }
  out.indices.resize(offset);
  for (std::size_t i = 0; i < hits.size(); ++i)
    for (std::uint32_t t : hits[i]) out.indices[out.grid[t].offset + out.grid[t].count++] = static_cast<std::uint32_t>(i);
  return out;
}

}  // namespace ml
