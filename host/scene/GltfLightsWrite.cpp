// gltfLightsDocument (GltfLights.hpp): a light set as nodes with
// KHR_lights_punctual point lights, through tinygltf's writer.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "host/scene/GltfLights.hpp"
#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

// Larger sets are written without indentation, which would double their size.
constexpr std::size_t kPrettyPrintUpTo = 4096;

void checkWritable(const gpu::PointLight& l, std::size_t i) {
  const float v[] = {l.position_radius.x, l.position_radius.y, l.position_radius.z, l.position_radius.w,
                     l.color.x,           l.color.y,           l.color.z};
  const std::string where = "light " + std::to_string(i);
  for (float f : v)
    if (!std::isfinite(f)) throw UserError("--write-lights: " + where + " has a non-finite value");
  if (!(l.position_radius.w > 0.0f)) throw UserError("--write-lights: " + where + " has a radius <= 0");
  if (l.color.x < 0.0f || l.color.y < 0.0f || l.color.z < 0.0f)
    throw UserError("--write-lights: " + where + " has a negative colour, which glTF cannot hold");
}

// The colour component c / intensity to write: its shortest decimal when the
// loader's product (in double) gives c back, else the exact quotient, whose
// product is within two double roundings of c and so rounds to c.
double colourFactor(float c, double intensity) {
  const double readable = scene_json::storable(static_cast<float>(static_cast<double>(c) / intensity));
  if (static_cast<float>(readable * intensity) == c) return readable;
  return static_cast<double>(c) / intensity;
}

// Colour and intensity whose product is the float colour again; positions and
// ranges take the shortest decimal that reads back to their float.
tinygltf::Light pointLight(const gpu::PointLight& l) {
  tinygltf::Light out;
  out.type = "point";
  out.range = scene_json::storable(l.position_radius.w);
  const float m = std::max({l.color.x, l.color.y, l.color.z});
  out.intensity = m <= 1.0f ? 1.0 : scene_json::storable(m);
  out.color = {colourFactor(l.color.x, out.intensity), colourFactor(l.color.y, out.intensity),
               colourFactor(l.color.z, out.intensity)};
  return out;
}

tinygltf::Node lightNode(const gpu::PointLight& l, std::size_t i) {
  tinygltf::Node node;
  node.name = "light " + std::to_string(i);
  node.translation = {scene_json::storable(l.position_radius.x), scene_json::storable(l.position_radius.y),
                      scene_json::storable(l.position_radius.z)};
  tinygltf::Value::Object ref;
  ref["light"] = tinygltf::Value(static_cast<int>(i));
  node.extensions["KHR_lights_punctual"] = tinygltf::Value(std::move(ref));
  return node;
}

}  // namespace

std::string gltfLightsDocument(const std::vector<gpu::PointLight>& lights, bool binary) {
  if (lights.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw UserError("--write-lights: too many lights for glTF's node indices");
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "manylights";
  tinygltf::Scene scene;
  scene.name = "lights";
  for (std::size_t i = 0; i < lights.size(); ++i) {
    checkWritable(lights[i], i);
    model.lights.push_back(pointLight(lights[i]));
    model.nodes.push_back(lightNode(lights[i], i));
    scene.nodes.push_back(static_cast<int>(i));
  }
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;
  std::ostringstream text;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, text, !binary && lights.size() <= kPrettyPrintUpTo, binary))
    throw UserError("--write-lights: the glTF writer failed");
  return text.str();
}

}  // namespace ml
