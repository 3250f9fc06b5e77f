#include "host/scene/GltfLights.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "host/scene/GltfModel.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

using scene_json::json;
constexpr const char* kExtension = "KHR_lights_punctual";

// One entry of the extension's light table.
struct TableEntry {
  std::string type;
  glm::vec3 intensity{1.0f};  // colour x intensity
  float range = 0.0f;         // 0: none given
};

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw UserError(where + ": " + what); }

// A finite JSON number, as double (colour x intensity is multiplied in double).
double number(const json& v, const std::string& where, const char* field) {
  if (!v.is_number()) fail(where, std::string("\"") + field + "\" must be a number (got " + scene_json::describe(v) + ")");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(where, std::string("\"") + field + "\" must be finite");
  return d;
}

glm::dvec3 colourOf(const json& light, const std::string& where) {
  const auto it = light.find("color");
  if (it == light.end()) return glm::dvec3(1.0);  // glTF's default
  if (!it->is_array() || it->size() != 3)
    fail(where, "\"color\" must be an array of 3 numbers (got " + scene_json::describe(*it) + ")");
  glm::dvec3 c;
  for (int i = 0; i < 3; ++i) {
    c[i] = number((*it)[static_cast<std::size_t>(i)], where, "color");
    if (c[i] < 0.0) fail(where, "\"color\" must not be negative (got " + scene_json::describe(*it) + ")");
  }
  return c;
}

TableEntry parseEntry(const json& light, const std::string& where) {
  if (!light.is_object()) fail(where, "must be an object (got " + scene_json::describe(light) + ")");
  TableEntry e;
  const auto type = light.find("type");
  if (type == light.end() || !type->is_string())
    fail(where, "\"type\" must be \"point\", \"spot\" or \"directional\"");
  e.type = type->get<std::string>();
  if (e.type != "point" && e.type != "spot" && e.type != "directional")
    fail(where, "unknown type \"" + e.type + "\" (point, spot or directional)");
  const glm::dvec3 colour = colourOf(light, where);
  double intensity = 1.0;
  if (const auto it = light.find("intensity"); it != light.end()) {
    intensity = number(*it, where, "intensity");
    if (intensity < 0.0) fail(where, "\"intensity\" must not be negative (got " + scene_json::describe(*it) + ")");
  }
  e.intensity = glm::vec3(colour * intensity);
  if (!std::isfinite(e.intensity.r) || !std::isfinite(e.intensity.g) || !std::isfinite(e.intensity.b))
    fail(where, "colour x intensity is too large for a float");
  if (const auto it = light.find("range"); it != light.end()) {
    const double r = number(*it, where, "range");
    e.range = static_cast<float>(r);
    if (!(r > 0.0) || !(e.range > 0.0f) || !std::isfinite(e.range))
      fail(where, "\"range\" must be > 0 (got " + scene_json::describe(*it) + ")");
  }
  return e;
}

// The file's light table; empty when it does not use the extension.
std::vector<TableEntry> lightTable(const tinygltf::Model& model, const std::string& path) {
  if (model.extensions_json_string.empty()) return {};
  const json root = json::parse(model.extensions_json_string, nullptr, false);
  if (!root.is_object()) return {};  // no "extensions" (tinygltf writes null) or one tinygltf rejected
  const auto ext = root.find(kExtension);
  if (ext == root.end()) return {};
  const std::string where = path + ": " + kExtension;
  if (!ext->is_object()) fail(where, "must be an object");
  const auto list = ext->find("lights");
  if (list == ext->end() || !list->is_array()) fail(where, "needs a \"lights\" array");
  std::vector<TableEntry> table;
  for (std::size_t i = 0; i < list->size(); ++i)
    table.push_back(parseEntry((*list)[i], where + " light " + std::to_string(i)));
  return table;
}

// The light each node places (-1: none), checked against the table for every
// node, in the scene or not.
std::vector<long> nodeLights(const tinygltf::Model& model, const std::string& path, std::size_t table_size) {
  std::vector<long> out(model.nodes.size(), -1);
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const std::string& text = model.nodes[n].extensions_json_string;
    if (text.empty()) continue;
    const json ext = json::parse(text, nullptr, false);
    if (!ext.is_object() || !ext.contains(kExtension)) continue;
    const std::string where = path + ": node " + std::to_string(n);
    const json& mine = ext[kExtension];
    const auto light = mine.is_object() ? mine.find("light") : mine.end();
    if (!mine.is_object() || light == mine.end() || !light->is_number_integer())
      fail(where, std::string(kExtension) + " needs a \"light\" index");
    const auto index = light->get<std::int64_t>();
    if (index < 0 || static_cast<std::uint64_t>(index) >= table_size)
      fail(where, "refers to light " + light->dump() + ", which does not exist (" + std::to_string(table_size) +
                      " in the light table)");
    out[n] = static_cast<long>(index);
  }
  return out;
}

// Places the table's lights along the scene's node tree, depth first.
struct Placer {
  const tinygltf::Model& model;
  const std::string& path;
  const std::vector<TableEntry>& table;
  const std::vector<long>& light_of;
  float threshold;
  GltfLightTable& out;
  std::vector<std::size_t> placements;

  void place(long light, const glm::mat4& world, std::size_t node) {
    const TableEntry& e = table[static_cast<std::size_t>(light)];
    ++placements[static_cast<std::size_t>(light)];
    if (e.type != "point") {
      ++(e.type == "spot" ? out.spot : out.directional);
      return;
    }
    const glm::vec3 p(world[3]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(path, "node " + std::to_string(node) + " places light " + std::to_string(light) +
                     " at a non-finite position");
    const float radius = e.range > 0.0f ? e.range : thresholdRadius(e.intensity, threshold);
    if (!(radius > 0.0f) || !std::isfinite(radius)) {
      ++out.dark;
      return;
    }
    out.lights.push_back(makeLight(p, radius, e.intensity));
  }

  void run() {
    struct Step {
      int node;
      glm::mat4 parent;
    };
    std::vector<Step> stack;
    const std::vector<int> roots = gltf_model::sceneRoots(model, path);
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::mat4(1.0f)});
    std::vector<char> seen(model.nodes.size(), 0);
    placements.assign(table.size(), 0);
    while (!stack.empty()) {
      const Step s = stack.back();
      stack.pop_back();
      if (s.node < 0 || static_cast<std::size_t>(s.node) >= model.nodes.size())
        fail(path, "the scene refers to node " + std::to_string(s.node) + ", which does not exist");
      const auto n = static_cast<std::size_t>(s.node);
      // glTF's nodes form trees: a second visit means a cycle or a shared child.
      if (seen[n]) fail(path, "node " + std::to_string(n) + " is reached twice (nodes must form trees)");
      seen[n] = 1;
      const tinygltf::Node& node = model.nodes[n];
      const glm::mat4 world = s.parent * gltf_model::localTransform(node, path, "node " + std::to_string(n));
      if (light_of[n] >= 0) place(light_of[n], world, n);
      for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world});
    }
    for (std::size_t count : placements) out.unplaced += count == 0 ? 1 : 0;
  }
};

std::string plural(std::size_t n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

}  // namespace

float thresholdRadius(const glm::vec3& intensity, float threshold) {
  const double brightest = std::max({intensity.r, intensity.g, intensity.b});
  if (!(brightest > 0.0)) return 0.0f;
  return static_cast<float>(std::sqrt(brightest / static_cast<double>(threshold)));
}

std::string GltfLightTable::skippedNote() const {
  std::vector<std::string> parts;
  if (spot) parts.push_back(plural(spot, "spot light") + " (no cone in the renderer)");
  if (directional) parts.push_back(plural(directional, "directional light") + " (no sun in the renderer)");
  if (dark) parts.push_back(plural(dark, "point light") + " without range and with zero intensity");
  if (unplaced) parts.push_back(plural(unplaced, "light") + " that no node of the scene places");
  if (parts.empty()) return "";
  std::string note = "skipped ";
  for (std::size_t i = 0; i < parts.size(); ++i)
    note += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return note + "; " + plural(lights.size(), "point light") + " used";
}

GltfLightTable gltf_model::readLights(const tinygltf::Model& model, const std::string& path, float threshold) {
  if (!(threshold > 0.0f) || !std::isfinite(threshold))
    throw UserError("--light-threshold: must be finite and > 0 (got " + std::to_string(threshold) + ")");
  GltfLightTable out;
  const std::vector<TableEntry> table = lightTable(model, path);
  const std::vector<long> light_of = nodeLights(model, path, table.size());
  out.table_size = table.size();
  if (table.empty()) return out;
  Placer{model, path, table, light_of, threshold, out, {}}.run();
  return out;
}

GltfLightTable loadGltfLights(const std::string& path, float threshold) {
  const tinygltf::Model model = gltf_model::readModel(path, false);
  GltfLightTable table = gltf_model::readLights(model, path, threshold);
  if (const std::string note = table.skippedNote(); !note.empty()) gltf_model::warnings().warn("{}: {}", path, note);
  return table;
}

bool isGltfPath(const std::string& path) {
  auto endsWith = [&](const std::string& ext) {
    return path.size() >= ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
  };
  return endsWith(".gltf") || endsWith(".glb");
}

}  // namespace ml
