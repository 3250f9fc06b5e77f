// The hashed technique's descriptor: names, parameters, light limit, factory.
#include "host/hashed/HashedAssigner.hpp"
#include "host/hashed/OctantMask.hpp"
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

}  // namespace ml
