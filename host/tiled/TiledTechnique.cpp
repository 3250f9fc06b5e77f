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
        countParam("tile", "auto", 1, kMaxTileSize, "tile size in pixels; auto: 16, 8 as the lights get small on "
                   "screen", {"auto", "0"}),
        choiceParam("tile_depth", "mask", {"none", "minmax", "mask"},
                    "per-tile depth culling: none, min/max bounds, or a 2.5D mask (the default: fewer evaluations "
                    "at every light count, and the fastest frame from 256k lights, docs/scaling.md)"),
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
