// The tiled technique's descriptor: names, parameters, factory.
#include "host/cl/KernelLimits.hpp"
#include "host/tiled/TiledAssigner.hpp"

namespace ml {

const TechniqueDescriptor& tiledTechnique() {
  static const TechniqueDescriptor d = [] {
    TechniqueDescriptor t;
    t.family = "tiled";
    t.names = {
        {"tiled-forward", Pipeline::Forward, "forward+: depth pre-pass, per-tile light culling (OpenCL), forward shading"},
        {"tiled-deferred", Pipeline::Deferred, "tiled deferred: per-tile light culling (OpenCL) over the G-buffer depth"},
    };
    t.params = {
        countParam("tile", "16", 1, kMaxTileSize, "tile size in pixels"),
        choiceParam("tile_depth", "minmax", {"none", "minmax", "mask"},
                    "per-tile depth culling: none, min/max bounds, or a 2.5D mask"),
        kernelShapeParam(),
    };
    t.make = [](const TechniqueContext& c) -> std::unique_ptr<LightAssigner> {
      return std::make_unique<TiledAssigner>(c.cl, c.params.count("tile"), parseTileDepthMode(c.params.text("tile_depth")),
                                             parseKernelShape(c.params.text("kernel_shape")));
    };
    return t;
  }();
  return d;
}

}  // namespace ml
