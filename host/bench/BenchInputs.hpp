#pragma once
// What a benchmark renders: one scene with its camera path, and the light sets
// to sweep. The scene is either
//   - a scene-suite folder of the thesis's program (geometry/, obj/, lights/,
//     camera/; see host/suite/NtiledSuite.hpp), or
//   - a folder in the project's own format (scene.glb|scene.gltf, camera.json,
//     lights.json, optionally light_volumes.json, like data/default/), or
//   - a .gltf/.glb file, with --camera and --lights given separately.
// Light-set items (comma-separated):
//   a JSON file (either light format); a file name under the suite's lights/
//   ("70#1x_1y_1z" or "70#1x_1y_1z.json"); "thesis" (suite: the light set the
//   thesis measured for each light count); "all" (suite: every light file); a
//   count N (suite: the thesis's set with N lights; glTF: N lights generated
//   in the scene's light volumes, seeded).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

struct BenchSceneArgs {
  std::string suite;          // folder or .gltf/.glb; empty: the project's data/default/
  std::string camera;         // camera path JSON (glTF scenes); empty: the folder's camera.json
  std::string light_volumes;  // boxes for generated lights (glTF scenes)
  float light_radius = 0;     // generated lights; 0: the volume file's or 1/20 of the scene size
  float light_density = 0;    // generated lights; > 0: radius from densityRadius() (LightSet.hpp)
  std::uint64_t seed = kThesisSeed;
  std::string geometry;       // suite: geometry file under geometry/
  bool allow_missing_meshes = false;
  std::optional<float> fovy, near_plane, far_plane;  // override the path's lens
  std::size_t resample = 0;   // > 0: resample the camera path to this many frames
};

struct BenchScene {
  std::string source;  // what was loaded, for reports
  std::string format;  // "ntiled-suite" | "gltf"
  std::string name;    // folder or file stem
  Scene scene;
  CameraPath cameras;
  std::vector<std::string> suite_light_files;  // suite only
  std::string default_lights;                  // a light file to use without --lights, or empty
  std::vector<std::string> missing_meshes;     // suite with --allow-missing-meshes
  std::string dir;                             // the folder, when the input is one
};

BenchScene loadBenchScene(const BenchSceneArgs& args);

struct LightSetInput {
  std::string label;  // "70#1x_1y_1z", "lights", "500 generated"
  std::string file;   // empty for generated sets
  std::vector<gpu::PointLight> lights;
};

// Resolves a comma-separated light-set list (see above); empty `list` means
// the scene's default light file. UserError naming `flag` on bad items.
std::vector<LightSetInput> resolveLightSets(const BenchScene& scene, const std::string& list,
                                            const BenchSceneArgs& args, const std::string& flag);

// Splits "a,b,,c" into {"a","b","c"} (empty items dropped, spaces trimmed).
std::vector<std::string> splitList(const std::string& text);

}  // namespace ml
