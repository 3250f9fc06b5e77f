// The hashed technique's descriptor: names, parameters, debug view, light limit, factory.
#include "host/hashed/HashedAssigner.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/hashed/OctreeCellView.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

std::string nodeSizeProblem(const std::string& text) {
  const char* expected = "a positive size, absolute (2.0) or relative to the light radius (0.5r)";
  if (text.empty()) return expected;
  try {
    hashed::parseNodeSize(text);
    return {};
  } catch (const UserError&) {
    return expected;
  }
}

}  // namespace

const TechniqueDescriptor& hashedTechnique() {
  static const TechniqueDescriptor d = [] {
    const char* what = "camera-independent linkless octree of perfect spatial hashes";
    TechniqueDescriptor t;
    t.family = "hashed";
    t.names = {{"hashed-forward", Pipeline::Forward, std::string("hashed shading, forward: ") + what},
               {"hashed-deferred", Pipeline::Deferred, std::string("hashed shading, deferred: ") + what}};
    t.params = {
        textParam("node_size", "0.5r", "minimal node size",
                  nodeSizeProblem),
        countParam("start_depth", "3", 0, 16, "octree start depth"),
        switchParam("geometry_mask", true, "keep only nodes that contain the scene's geometry"),
        switchParam("octant_masks", true, "skip lights that miss the point's octant of its deepest cell"),
    };
    t.debug_views = {{"octree-cell", "write each pixel's octree cell (the node holding its surface point) as a "
                                     "colour to this image (.png/.exr); empty cells grey"}};
    t.max_lights = hashed::kMaxHashedLights;
    t.make = [](const TechniqueContext& c) -> std::unique_ptr<LightAssigner> {
      hashed::HashedConfig config;
      config.node_size = c.params.text("node_size");
      config.start_depth = c.params.count("start_depth");
      config.geometry_mask = c.params.on("geometry_mask");
      config.octant_masks = c.params.on("octant_masks");
      auto a = std::make_unique<HashedAssigner>(c.name.name, config);
      a->setScene(c.scene);
      return a;
    };
    return t;
  }();
  return d;
}

std::vector<float> HashedAssigner::debugViewRgba(const std::string& view, const DebugViewInputs& frame) {
  if (view != "octree-cell") return {};
  if (!structure_ || !structure_->built())
    return std::vector<float>(std::size_t(frame.width) * frame.height * 4, 0.0f);
  return hashed::octreeCellViewRgba(structure_->linkless(), frame);
}

}  // namespace ml
