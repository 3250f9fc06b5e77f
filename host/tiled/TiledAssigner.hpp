#pragma once
// Tiled shading as a LightAssigner (forward+ and tiled deferred): per frame the
// TileLightCuller builds the light grid and index list on the CL device,
// straight into buffers that the shaders read (lookup_tiled.glsl).
// tiledTechnique(): the descriptor the registry lists (TiledTechnique.cpp).
#include <memory>

#include "gl/SharedBuffer.hpp"
#include "host/assign/LightAssigner.hpp"
#include "host/assign/TechniqueDescriptor.hpp"
#include "host/tiled/TileLightCuller.hpp"

namespace ml {

// The automatic tile (--tile auto): 16 px, and 8 px once the lights get small
// on screen (autoTileSize). The lists' evaluations / exact bound on the
// default scene at constant density grow as the tile / light pixels ratio
// grows, faster than the clusters' (a tile has no depth slices): at 1M lights
// 6.95 at 16 px against 3.13 at 8 px (minmax), 4.37 against 2.31 (mask).
constexpr double kTilePerLightPixel = 0.14;
unsigned autoTileSize(double light_pixels);

class TiledAssigner final : public LightAssigner {
 public:
  // tile_size 0: autoTileSize() of each frame's lights.
  TiledAssigner(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape = KernelShape::Auto);
  bool needsDepth() const override { return mode_ != TileDepthMode::None; }
  void assign(const FrameInputs& in) override;
  std::string lookupShader() const override { return "tiled/lookup_tiled.glsl"; }
  ShaderDefines shaderDefines() const override;
  void bindForShading(const ShaderProgram& program) const override;
  std::size_t memoryBytes() const override;
  std::vector<std::pair<std::string, double>> stats() const override;

 private:
  void useTile(unsigned tile_size);
  ClRuntime& rt_;
  unsigned tile_size_;
  TileDepthMode mode_;
  KernelShape shape_;
  std::unique_ptr<TileLightCuller> culler_;  // the last frame's tile size
  double light_pixels_ = 0.0;          // coveringLightPixels() of the last frame (auto tile only)
  std::unique_ptr<SharedBuffer> grid_;
  std::unique_ptr<SharedBuffer> indices_;
  std::uint32_t last_total_ = 0;
};

const TechniqueDescriptor& tiledTechnique();

}  // namespace ml
