#pragma once
// What a run renders: one scene with its camera path, and its lights. Both
// `render`/`view` (one light set: loadSceneInputs) and `bench`/
// `compare-reference` (light-set lists: loadRunScene + resolveLightSets)
// resolve their flags here, the same way. The scene is either
//   - a scene-suite folder of the thesis's program (geometry/, obj/, lights/,
//     camera/; see host/suite/NtiledSuite.hpp), or
//   - a folder in the project's own format (scene.glb|scene.gltf, camera.json,
//     lights.json, optionally light_volumes.json, like data/default/), or
//   - a .gltf/.glb file, with --camera and --lights given separately.
// Without --lights a scene's own lights are used: the folder's lights.json,
// else the point lights its glTF carries (KHR_lights_punctual,
// host/scene/GltfLights.hpp), else (render, view) data/default's.
// Light-set items (comma-separated):
//   a JSON file (either light format); a .gltf/.glb file (its point lights,
//   its meshes ignored); a file name under the suite's lights/
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

// The scene and light flags of every command (host/app/InputFlags.hpp).
struct SceneInputArgs {
  std::string scene;          // folder or .gltf/.glb; empty: the project's data/default/
  std::string lights;         // render/view: a count, JSON or glTF file; bench: a light-set list; empty: the scene's
  std::string camera;         // camera or path JSON; empty: the folder's camera.json
  std::string light_volumes;  // boxes for generated lights; empty: the folder's light_volumes.json or the bounds
  float light_radius = 0;     // generated lights; 0: the volume file's or 1/20 of the scene size
  float light_density = 0;    // generated lights; > 0: radius from densityRadius() (LightSet.hpp)
  std::uint64_t seed = kThesisSeed;
  float light_threshold = kDefaultLightThreshold;  // radius of glTF lights without range (GltfLights.hpp)
  std::string write_lights;   // render/bench: write the light set in use to this .gltf/.glb
  std::string geometry;       // suite: geometry file under geometry/
  bool allow_missing_meshes = false;
  std::optional<float> fovy, near_plane, far_plane;  // override the path's lens
  std::size_t resample = 0;   // > 0: resample the camera path to this many frames
};

// "1000" -> 1000 (up to 2^64-1, so that huge counts get a limit message rather
// than "not a file"); false when `text` is not a plain decimal count.
bool parseLightCount(const std::string& text, std::uint64_t& count);

struct RunScene {
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

// UserError naming `flag` for an input that is no scene. fit_camera: a glTF
// file without --camera is viewed from outside its bounds (else refused).
RunScene loadRunScene(const SceneInputArgs& args, const std::string& flag = "--scene", bool fit_camera = false);

struct LightSetInput {
  std::string label;  // "70#1x_1y_1z", "lights", "500 generated"
  std::string file;   // empty for generated sets
  std::string source;  // "generated", "json" or "gltf" (a glTF file's or the scene's own point lights)
  std::vector<gpu::PointLight> lights;
};

// Resolves args.lights as a comma-separated light-set list (see above); empty
// means the scene's default light file. UserError naming `flag` on bad items.
std::vector<LightSetInput> resolveLightSets(const RunScene& scene, const SceneInputArgs& args,
                                            const std::string& flag);

// One scene and one light set (render, view): args.lights is a count, a JSON
// or a glTF file; empty: the scene's own lights (see above), else
// data/default's.
struct SceneInputs {
  Scene scene;
  std::vector<gpu::PointLight> lights;
  CameraPath cameras;
  std::string lights_label;   // "1024 (data/default/lights.json)" for reports
  std::string lights_source;  // as LightSetInput::source
  std::string lights_file;    // where they were read (reportPath), empty when generated
};
SceneInputs loadSceneInputs(const SceneInputArgs& args);

// --write-lights, before anything loads: empty, or a writable .gltf/.glb path.
void checkWriteLightsFlag(const std::string& path);
// Writes `lights` there (GltfLights.hpp) atomically; nothing when path is empty.
void writeLightsGltf(const std::string& path, const std::vector<gpu::PointLight>& lights);

// Splits "a,b,,c" into {"a","b","c"} (empty items dropped, spaces trimmed).
std::vector<std::string> splitList(const std::string& text);

}  // namespace ml
