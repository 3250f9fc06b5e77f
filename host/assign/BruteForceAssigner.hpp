#pragma once
// Every light for every shaded point: the reference that the other techniques
// are checked against, and the thesis's "naive" forward/deferred shading.
#include "host/assign/LightAssigner.hpp"
#include "host/assign/TechniqueDescriptor.hpp"

namespace ml {

class BruteForceAssigner final : public LightAssigner {
 public:
  void assign(const FrameInputs&) override {}
  std::string lookupShader() const override { return "assign/lookup_brute.glsl"; }
  void bindForShading(const ShaderProgram&) const override {}
};

// `forward` and `deferred`, no parameters (BruteForceTechnique.cpp).
const TechniqueDescriptor& bruteForceTechnique();

}  // namespace ml
