#include "host/app/SceneInputs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/app/InputChecks.hpp"
#include "host/bench/OutputFiles.hpp"
#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"

namespace ml {

SceneInputs loadSceneInputs(const SceneInputArgs& args) {
  std::uint64_t count = 0;
  const bool generated = parseLightCount(args.lights, count);
  if (args.light_radius != 0.0f && !generated)
    throw UserError("--light-radius: only generated lights (--lights N) take a radius; light files carry their own");
  checkLightDensityFlag(args.light_density, args.light_radius, generated);
  if (generated) checkLightCount("--lights", count, "generated");  // before any memory is spent on them
  SceneInputs out;
  const bool default_scene = args.scene.empty();
  const std::string scene_path = default_scene ? dataPath("default/scene.glb") : args.scene;
  out.scene = loadGltfScene(scene_path);

  if (args.lights.empty()) {
    const std::string p = dataPath("default/lights.json");
    out.lights = loadLightsJson(p);
    out.lights_label = std::to_string(out.lights.size()) + " (" + reportPath(p) + ")";
  } else if (generated) {
    std::string vol_path = args.light_volumes;
    if (vol_path.empty() && default_scene) vol_path = dataPath("default/light_volumes.json");
    out.lights = generateLightsIn(vol_path, out.scene.bounds.min, out.scene.bounds.max,
                                  static_cast<std::uint32_t>(count), args.seed, args.light_radius,
                                  args.light_density);
    out.lights_label = std::to_string(count) + " generated (seed " + std::to_string(args.seed) +
                       densityLabel(args.light_density, out.lights) + ")";
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
