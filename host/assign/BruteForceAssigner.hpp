#pragma once
// Every light for every shaded point: the reference that the other techniques
// are checked against, and the thesis's "naive" forward/deferred shading.
#include "host/assign/LightAssigner.hpp"

namespace ml {

class BruteForceAssigner final : public LightAssigner {
 public:
  std::string name() const override { return "brute"; }
  void assign(const FrameInputs&) override {}
  std::string lookupShader() const override { return "lookup_brute.glsl"; }
  void bindForShading(const ShaderProgram&) const override {}
};

}  // namespace ml
