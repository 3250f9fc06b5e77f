#pragma once
// What a run renders: scene geometry, the light set and the camera path,
// resolved from command-line values (defaults: the project's data/default/).
#include <cstdint>
#include <string>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

struct SceneInputArgs {
  std::string scene;        // .gltf/.glb; empty: data/default/scene.glb
  std::string lights;       // a count ("1000") or a JSON file; empty: data/default/lights.json
  std::string camera;       // camera or path JSON; empty: data/default/camera.json
  std::string light_volumes;  // JSON boxes for generated lights; empty: scene's default or its bounds
  float light_radius = 0;   // generated lights; 0: the volume file's radius or 1/20 of the scene size
  float light_density = 0;  // generated lights; > 0: radius from densityRadius() (LightSet.hpp)
  std::uint64_t seed = kThesisSeed;
};

struct SceneInputs {
  Scene scene;
  std::vector<gpu::PointLight> lights;
  CameraPath cameras;
  std::string lights_label;  // "1024 (data/default/lights.json)" for reports
};

SceneInputs loadSceneInputs(const SceneInputArgs& args);


}  // namespace ml
