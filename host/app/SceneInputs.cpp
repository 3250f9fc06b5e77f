#include "host/app/SceneInputs.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

bool parseCount(const std::string& s, std::uint32_t& out) {
  if (s.empty()) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

}  // namespace

SceneInputs loadSceneInputs(const SceneInputArgs& args) {
  SceneInputs out;
  const bool default_scene = args.scene.empty();
  const std::string scene_path = default_scene ? dataPath("default/scene.glb") : args.scene;
  out.scene = loadGltfScene(scene_path);

  std::uint32_t count = 0;
  if (args.lights.empty()) {
    const std::string p = dataPath("default/lights.json");
    out.lights = loadLightsJson(p);
    out.lights_label = std::to_string(out.lights.size()) + " (" + p + ")";
  } else if (parseCount(args.lights, count)) {
    std::string vol_path = args.light_volumes;
    if (vol_path.empty() && default_scene) vol_path = dataPath("default/light_volumes.json");
    out.lights = generateLightsIn(vol_path, out.scene.bounds.min, out.scene.bounds.max, count, args.seed,
                                  args.light_radius);
    out.lights_label = std::to_string(count) + " generated (seed " + std::to_string(args.seed) + ")";
  } else {
    if (args.lights.size() > 0 && args.lights[0] == '-')
      throw UserError("--lights: expected a light count or a JSON file, got '" + args.lights + "'");
    out.lights = loadLightsJson(args.lights);
    out.lights_label = std::to_string(out.lights.size()) + " (" + args.lights + ")";
  }

  const std::string cam_path = args.camera.empty() ? dataPath("default/camera.json") : args.camera;
  if (args.camera.empty() && !default_scene) {
    // A custom scene without a camera: look at its bounds from outside.
    Camera c;
    const glm::vec3 center = 0.5f * (out.scene.bounds.min + out.scene.bounds.max);
    const float size = glm::length(out.scene.bounds.max - out.scene.bounds.min);
    c.center = center;
    c.eye = center + glm::vec3(0.6f, 0.4f, 0.8f) * size;
    c.near_plane = size * 1e-3f;
    c.far_plane = size * 4.0f;
    out.cameras.frames = {c};
  } else {
    out.cameras = loadCameraJson(cam_path);
  }
  return out;
}

}  // namespace ml
