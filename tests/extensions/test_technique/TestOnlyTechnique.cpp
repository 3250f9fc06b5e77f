// A technique that exists only in the test binary: brute force under its own
// names with a parameter of its own, registered at start-up. It is the whole
// diff a new technique needs outside its shaders and kernels: an assigner, a
// descriptor and one registration (a built-in one adds a line to
// host/techniques/Registry.cpp instead). tests/assign/techniques_registry_test.cpp
// finds it in `techniques`, `render --help`, `bench --help` and the checks.
#include "host/techniques/Registry.hpp"

namespace ml {
namespace {

class KnobBruteAssigner final : public LightAssigner {
 public:
  explicit KnobBruteAssigner(unsigned knob) : knob_(knob) {}
  void assign(const FrameInputs&) override {}
  std::string lookupShader() const override { return "assign/lookup_brute.glsl"; }
  void bindForShading(const ShaderProgram&) const override {}
  std::vector<std::pair<std::string, double>> stats() const override { return {{"test knob", double(knob_)}}; }

 private:
  unsigned knob_;
};

[[maybe_unused]] const bool kRegistered = [] {
  TechniqueDescriptor t;
  t.family = "test brute force";
  t.names = {{"test-brute-forward", Pipeline::Forward, "test only: brute-force forward with a knob"},
             {"test-brute-deferred", Pipeline::Deferred, "test only: brute-force deferred with a knob"}};
  t.params = {countParam("test_knob", "2", 1, 8, "a test-only parameter, reported as the stat 'test knob'")};
  t.make = [](const TechniqueContext& c) -> std::unique_ptr<LightAssigner> {
    return std::make_unique<KnobBruteAssigner>(c.params.count("test_knob"));
  };
  registerTechnique(t);
  return true;
}();

}  // namespace
}  // namespace ml
