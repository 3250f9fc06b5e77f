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

class TiledAssigner final : public LightAssigner {
 public:
  TiledAssigner(ClRuntime& rt, unsigned tile_size, TileDepthMode mode, KernelShape shape = KernelShape::Auto);
  bool needsDepth() const override { return culler_.mode() != TileDepthMode::None; }
  void assign(const FrameInputs& in) override;
  std::string lookupShader() const override { return "tiled/lookup_tiled.glsl"; }
  ShaderDefines shaderDefines() const override;
  void bindForShading(const ShaderProgram& program) const override;
  std::size_t memoryBytes() const override;
  std::vector<std::pair<std::string, double>> stats() const override;

 private:
  ClRuntime& rt_;
  TileLightCuller culler_;
  std::unique_ptr<SharedBuffer> grid_;
  std::unique_ptr<SharedBuffer> indices_;
  std::uint32_t last_total_ = 0;
};

const TechniqueDescriptor& tiledTechnique();

}  // namespace ml
