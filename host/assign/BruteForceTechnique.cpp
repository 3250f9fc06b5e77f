// The brute-force technique's descriptor: the reference, no parameters.
#include "host/assign/BruteForceAssigner.hpp"

namespace ml {

const TechniqueDescriptor& bruteForceTechnique() {
  static const TechniqueDescriptor d = [] {
    TechniqueDescriptor t;
    t.family = "brute force";
    t.names = {{"forward", Pipeline::Forward, "brute-force forward shading: every light for every fragment"},
               {"deferred", Pipeline::Deferred, "brute-force deferred shading: G-buffer, then every light per pixel"}};
    t.make = [](const TechniqueContext&) -> std::unique_ptr<LightAssigner> {
      return std::make_unique<BruteForceAssigner>();
    };
    return t;
  }();
  return d;
}

}  // namespace ml
