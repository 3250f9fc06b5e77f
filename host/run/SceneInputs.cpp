#include "host/run/SceneInputs.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>

#include "host/run/OutputFiles.hpp"
#include "host/scene/GltfLights.hpp"
#include "host/suite/CameraPathInterp.hpp"
#include "host/suite/NtiledSuite.hpp"
#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

bool isGltf(const fs::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

// A scene without a camera path: look at its bounds from outside.
CameraPath cameraOutside(const Scene& scene) {
  Camera c;
  const glm::vec3 center = 0.5f * (scene.bounds.min + scene.bounds.max);
  const float size = glm::length(scene.bounds.max - scene.bounds.min);
  c.center = center;
  c.eye = center + glm::vec3(0.6f, 0.4f, 0.8f) * size;
  c.near_plane = size * 1e-3f;
  c.far_plane = size * 4.0f;
  CameraPath path;
  path.frames = {c};
  return path;
}

// `count` lights generated in the scene's light volumes: --light-volumes, else
// the scene folder's light_volumes.json, else the scene's bounds.
std::vector<gpu::PointLight> generateSceneLights(const RunScene& scene, std::uint32_t count,
                                                 const SceneInputArgs& args) {
  std::string vol = args.light_volumes;
  if (vol.empty() && !scene.dir.empty() && fs::is_regular_file(fs::path(scene.dir) / "light_volumes.json"))
    vol = (fs::path(scene.dir) / "light_volumes.json").string();
  return generateLightsIn(vol, scene.scene.bounds.min, scene.scene.bounds.max, count, args.seed, args.light_radius,
                          args.light_density);
}

// A light file's set: a glTF's point lights or a light JSON. An empty glTF
// set is refused here: it is what a file without the extension gives.
std::vector<gpu::PointLight> loadLightFile(const std::string& file, float threshold) {
  if (!isGltfPath(file)) return loadLightsJson(file);
  GltfLightTable table = loadGltfLights(file, threshold);
  if (table.lights.empty())
    throw UserError(file + ": no point lights to use (KHR_lights_punctual, " + std::to_string(table.table_size) +
                    " in its light table)");
  return std::move(table.lights);
}

// A light-set item that names a file: as given, or (suite) under its lights/.
std::string lightFileOf(const RunScene& scene, const std::string& item, const std::string& flag) {
  const bool suite = scene.format == "ntiled-suite";
  std::string file = item;
  if (!fs::is_regular_file(file) && suite) {
    const fs::path dir = fs::path(scene.dir) / "lights";
    for (const fs::path& cand : {dir / item, dir / (item + ".json")})
      if (fs::is_regular_file(cand)) file = cand.string();
  }
  if (!fs::is_regular_file(file))
    throw UserError(flag + ": light set '" + item + "' is not a file" +
                    (suite ? " (nor a name under " + scene.dir + "/lights)" : ""));
  return file;
}

}  // namespace

bool parseLightCount(const std::string& text, std::uint64_t& count) {
  if (text.empty()) return false;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), count);
  if (ec == std::errc::result_out_of_range) {
    count = UINT64_MAX;
    return text.find_first_not_of("0123456789") == std::string::npos;
  }
  return ec == std::errc() && p == text.data() + text.size();
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const auto comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

RunScene loadRunScene(const SceneInputArgs& args, const std::string& flag, bool fit_camera) {
  RunScene out;
  const std::string input = args.scene.empty() ? dataPath("default") : args.scene;
  const fs::path p(input);
  std::error_code ec;
  if (fs::is_directory(p, ec) && isNtiledSuiteDir(input)) {
    SuiteLoadOptions o;
    o.geometry = args.geometry;
    o.allow_missing_meshes = args.allow_missing_meshes;
    SuiteScene s = loadNtiledSuite(input, o);
    out.format = "ntiled-suite";
    out.source = s.geometry_file;
    out.name = s.name;
    out.scene = std::move(s.scene);
    out.cameras = std::move(s.cameras);
    out.suite_light_files = s.light_files;
    out.missing_meshes = s.missing_meshes;
    out.dir = input;
    const auto thesis = thesisLightFiles(s.light_files);
    if (!thesis.empty()) out.default_lights = thesis.front();
    if (!args.camera.empty()) out.cameras = loadCameraJson(args.camera);
  } else if (fs::is_directory(p, ec)) {
    fs::path scene_file;
    for (const char* n : {"scene.glb", "scene.gltf"})
      if (fs::is_regular_file(p / n)) scene_file = p / n;
    if (scene_file.empty())
      throw UserError(flag + ": '" + input +
                      "' is neither a scene-suite folder (geometry/, obj/, lights/, camera/camera.json) nor a "
                      "folder with scene.glb or scene.gltf");
    out.format = "gltf";
    out.source = scene_file.string();
    out.name = p.lexically_normal().filename().string();
    if (out.name.empty()) out.name = p.lexically_normal().parent_path().filename().string();
    out.scene = loadGltfScene(scene_file.string(), args.light_threshold);
    out.dir = input;
    if (args.camera.empty() && !fs::is_regular_file(p / "camera.json"))
      throw UserError("--camera: no camera path given and '" + (p / "camera.json").string() + "' does not exist");
    out.cameras = loadCameraJson(args.camera.empty() ? (p / "camera.json").string() : args.camera);
    if (fs::is_regular_file(p / "lights.json")) out.default_lights = (p / "lights.json").string();
  } else if (isGltf(p)) {
    out.format = "gltf";
    out.source = input;
    out.name = stem(input);
    out.scene = loadGltfScene(input, args.light_threshold);  // names the file when it is missing or broken
    if (args.camera.empty() && !fit_camera)
      throw UserError("--camera: a glTF scene file needs a camera path (--camera FILE.json)");
    out.cameras = args.camera.empty() ? cameraOutside(out.scene) : loadCameraJson(args.camera);
  } else {
    throw UserError(flag + ": '" + input + "' does not exist or is not a scene folder or .gltf/.glb file");
  }
  for (Camera& c : out.cameras.frames) {
    if (args.fovy) c.fovy_degrees = *args.fovy;
    if (args.near_plane) c.near_plane = *args.near_plane;
    if (args.far_plane) c.far_plane = *args.far_plane;
  }
  if (args.resample > 0) out.cameras = resampleCameraPath(out.cameras, args.resample);
  return out;
}

namespace {

// A light file's set, labelled as results name it (no machine paths).
LightSetInput lightFileSet(const RunScene& scene, const std::string& file, float threshold) {
  LightSetInput s;
  s.file = reportPath(file);
  s.label = stem(file);
  if (s.label == "lights" && !scene.name.empty()) s.label = scene.name + "/lights";
  s.source = isGltfPath(file) ? "gltf" : "json";
  s.lights = loadLightFile(file, threshold);
  if (s.lights.empty()) throw UserError(file + ": the light set is empty");
  return s;
}

// The suite's thesis light file with `count` lights.
std::string suiteFileWithCount(const RunScene& scene, std::uint64_t count, const std::string& item,
                               const std::string& flag) {
  std::string match;
  for (const auto& f : thesisLightFiles(scene.suite_light_files))
    if (lightCountFromFileName(f) == count) match = f;
  if (match.empty())
    throw UserError(flag + ": the suite has no light set with " + item + " lights (see " + scene.dir + "/lights)");
  return match;
}

LightSetInput generatedSet(const RunScene& scene, std::uint64_t count, const std::string& item,
                           const SceneInputArgs& args, const std::string& flag) {
  if (count == 0) throw UserError(flag + ": a generated light set needs at least one light");
  checkLightCount(flag, count, "generated");  // before any memory is spent on them
  LightSetInput s;
  s.lights = generateSceneLights(scene, static_cast<std::uint32_t>(count), args);
  s.label = item + " generated" + densityLabel(args.light_density, s.lights);
  s.source = "generated";
  return s;
}

}  // namespace

std::vector<LightSetInput> resolveLightSets(const RunScene& scene, const SceneInputArgs& args,
                                            const std::string& flag) {
  std::vector<std::string> items = splitList(args.lights);
  if (items.empty() && scene.default_lights.empty() && !scene.scene.lights.empty()) {
    checkLightDensityFlag(args.light_density, args.light_radius, false);
    return {LightSetInput{scene.name + "/gltf", reportPath(scene.source), "gltf", scene.scene.lights}};
  }
  if (items.empty()) {
    if (scene.default_lights.empty())
      throw UserError(flag + ": no light set given and the scene has no default light file nor glTF lights");
    items = {scene.default_lights};
  }
  const bool suite = scene.format == "ntiled-suite";
  // A density applies to generated sets only: some item must be one.
  bool generates = false;
  for (const std::string& item : items) {
    std::uint64_t n = 0;
    generates |= !suite && parseLightCount(item, n);
  }
  checkLightDensityFlag(args.light_density, args.light_radius, generates);
  std::vector<LightSetInput> out;
  for (const std::string& item : items) {
    std::uint64_t count = 0;
    if (item == "thesis" || item == "all") {
      if (!suite) throw UserError(flag + ": '" + item + "' needs a scene-suite folder (--suite)");
      const auto files = item == "all" ? scene.suite_light_files : thesisLightFiles(scene.suite_light_files);
      if (files.empty()) throw UserError(flag + ": the suite has no light files under " + scene.dir + "/lights");
      for (const auto& f : files) out.push_back(lightFileSet(scene, f, args.light_threshold));
    } else if (parseLightCount(item, count)) {
      out.push_back(suite ? lightFileSet(scene, suiteFileWithCount(scene, count, item, flag), args.light_threshold)
                          : generatedSet(scene, count, item, args, flag));
    } else {
      out.push_back(lightFileSet(scene, lightFileOf(scene, item, flag), args.light_threshold));
    }
  }
  return out;
}

SceneInputs loadSceneInputs(const SceneInputArgs& args) {
  std::uint64_t count = 0;
  const bool generated = parseLightCount(args.lights, count);
  if (args.light_radius != 0.0f && !generated)
    throw UserError("--light-radius: only generated lights (--lights N) take a radius; light files carry their own");
  checkLightDensityFlag(args.light_density, args.light_radius, generated);
  if (generated) checkLightCount("--lights", count, "generated");  // before any memory is spent on them
  if (!generated && !args.lights.empty() && args.lights[0] == '-')
    throw UserError("--lights: expected a light count, a JSON or a glTF file, got '" + args.lights + "'");
  RunScene scene = loadRunScene(args, "--scene", true);
  SceneInputs out;
  if (generated) {
    out.lights = generateSceneLights(scene, static_cast<std::uint32_t>(count), args);
    out.lights_label = std::to_string(count) + " generated (seed " + std::to_string(args.seed) +
                       densityLabel(args.light_density, out.lights) + ")";
    out.lights_source = "generated";
  } else if (args.lights.empty() && scene.default_lights.empty() && !scene.scene.lights.empty()) {
    out.lights = scene.scene.lights;  // the glTF's own
    out.lights_file = reportPath(scene.source);
    out.lights_source = "gltf";
    out.lights_label = std::to_string(out.lights.size()) + " (" + out.lights_file + ", KHR_lights_punctual)";
  } else {
    // Without --lights: the scene folder's lights.json, else data/default's (a glTF file has none).
    const std::string file = !args.lights.empty()             ? args.lights
                             : !scene.default_lights.empty() ? scene.default_lights
                                                             : dataPath("default/lights.json");
    out.lights = loadLightFile(file, args.light_threshold);
    out.lights_file = reportPath(file);
    out.lights_source = isGltfPath(file) ? "gltf" : "json";
    out.lights_label = std::to_string(out.lights.size()) + " (" + (args.lights.empty() ? reportPath(file) : file) + ")";
  }
  out.scene = std::move(scene.scene);
  out.cameras = std::move(scene.cameras);
  return out;
}

void checkWriteLightsFlag(const std::string& path) {
  if (path.empty()) return;
  if (!isGltfPath(path))
    throw UserError("--write-lights: expected a .gltf or .glb file name, got '" + path + "'");
  requireOutputFile("--write-lights", path);
}

void writeLightsGltf(const std::string& path, const std::vector<gpu::PointLight>& lights) {
  if (path.empty()) return;
  writeFileAtomically("--write-lights", path, gltfLightsDocument(lights, fs::path(path).extension() == ".glb"));
}

}  // namespace ml
