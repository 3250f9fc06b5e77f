// A GI pass that exists only in the test binary: a constant ambient term,
// indirect = G-buffer albedo x the colour parameter `ambient` (R:G:B),
// registered at start-up. It is the whole diff a new GI pass needs outside
// its shaders and kernels: a GiPass, a descriptor and one registration (a
// built-in one adds a line to host/gi/Registry.cpp instead); no front end
// changes. tests/gi/gi_registry_test.cpp finds it in `render --help`, renders
// it through `render` and `bench --gi`, and drives it through the viewer's
// GI state. The work is done on the host (read back, add, upload): a test
// pass needs no shader, and the readback makes its arithmetic exact to check.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "gl/GlCheck.hpp"
#include "host/gi/Registry.hpp"
#include "extensions/ambient_gi/TestOnlyGiPass.hpp"

namespace ml::test {
namespace {

std::vector<float> readTexture(GLuint tex, GLenum format, std::size_t channels, unsigned w, unsigned h) {
  std::vector<float> px(std::size_t(w) * h * channels);
  glGetTextureImage(tex, 0, format, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
  glCheck("reading a G-buffer texture (test ambient pass)");
  return px;
}

class AmbientGiPass final : public GiPass {
 public:
  explicit AmbientGiPass(const glm::vec3& c) : c_(c) {}
  void update(const GiSceneInputs&) override { ++updates_; }
  void addIndirect(const GiFrameInputs& in) override {
    const unsigned w = in.width, h = in.height;
    const std::vector<float> albedo = readTexture(in.albedo, GL_RGBA, 4, w, h);
    const std::vector<float> depth = readTexture(in.depth, GL_DEPTH_COMPONENT, 1, w, h);
    std::vector<float> color = readTexture(in.color, GL_RGBA, 4, w, h);
    indirect_.assign(color.size(), 0.0f);
    for (std::size_t p = 0; p < depth.size(); ++p) {
      if (depth[p] <= 0.0f) continue;  // reversed Z: 0 is the far plane, nothing seen
      for (int k = 0; k < 3; ++k) indirect_[4 * p + k] = albedo[4 * p + k] * c_[k];
      indirect_[4 * p + 3] = 1.0f;
      for (int k = 0; k < 3; ++k) color[4 * p + k] += indirect_[4 * p + k];
    }
    glTextureSubImage2D(in.color, 0, 0, 0, GLsizei(w), GLsizei(h), GL_RGBA, GL_FLOAT, color.data());
    glCheck("adding the ambient term (test ambient pass)");
  }
  std::vector<float> indirectRgba() const override { return indirect_; }
  std::size_t memoryBytes() const override { return indirect_.size() * sizeof(float); }
  GiUpdateCounts updateCounts() const override { return {updates_, 0}; }
  GiStats stats() const override {
    GiStats s;
    s.json["gi_ambient"] = {c_.x, c_.y, c_.z};
    s.json["gi_ambient_updates"] = updates_;
    s.lines.push_back("gi test-ambient: " + std::to_string(updates_) + " updates");
    return s;
  }

 private:
  glm::vec3 c_;
  std::vector<float> indirect_;
  std::size_t updates_ = 0;
};

}  // namespace

std::string ambientProblem(const std::string& text) {
  glm::vec3 c;
  return parseAmbient(text, c) ? "" : "R:G:B, three non-negative numbers";
}

bool parseAmbient(const std::string& text, glm::vec3& c) {
  std::istringstream in(text);
  char colon1 = 0, colon2 = 0;
  in >> c.x >> colon1 >> c.y >> colon2 >> c.z;
  if (!in || colon1 != ':' || colon2 != ':' || in.peek() != std::char_traits<char>::eof()) return false;
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(c[k]) || c[k] < 0.0f) return false;
  return true;
}

namespace {

[[maybe_unused]] const bool kRegistered = [] {
  GiDescriptor d;
  d.name = kAmbientGiName;
  d.summary = "test only: indirect = albedo x a constant colour";
  d.params = {textParam("ambient", "0.25:0.5:0.75", "the constant colour (R:G:B) times the albedo", ambientProblem)};
  d.make = [](const GiContext& c) -> std::unique_ptr<GiPass> {
    glm::vec3 colour;
    parseAmbient(c.params.text("ambient"), colour);
    return std::make_unique<AmbientGiPass>(colour);
  };
  registerGi(d);
  return true;
}();

}  // namespace
}  // namespace ml::test
