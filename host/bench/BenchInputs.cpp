#include "host/bench/BenchInputs.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>

#include "host/bench/OutputFiles.hpp"
#include "host/suite/CameraPathInterp.hpp"
#include "host/suite/NtiledSuite.hpp"
#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

bool parseCount(const std::string& s, std::uint32_t& out) {
  if (s.empty()) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

bool isGltf(const fs::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

}  // namespace

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

BenchScene loadBenchScene(const BenchSceneArgs& args) {
  BenchScene out;
  const std::string input = args.suite.empty() ? dataPath("default") : args.suite;
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
      throw UserError("--suite: '" + input +
                      "' is neither a scene-suite folder (geometry/, obj/, lights/, camera/camera.json) nor a "
                      "folder with scene.glb or scene.gltf");
    out.format = "gltf";
    out.source = scene_file.string();
    out.name = p.lexically_normal().filename().string();
    if (out.name.empty()) out.name = p.lexically_normal().parent_path().filename().string();
    out.scene = loadGltfScene(scene_file.string());
    out.dir = input;
    const std::string cam = args.camera.empty() ? (p / "camera.json").string() : args.camera;
    if (!fs::is_regular_file(cam))
      throw UserError("--camera: no camera path given and '" + (p / "camera.json").string() + "' does not exist");
    out.cameras = loadCameraJson(cam);
    if (fs::is_regular_file(p / "lights.json")) out.default_lights = (p / "lights.json").string();
  } else if (isGltf(p)) {
    out.format = "gltf";
    out.source = input;
    out.name = stem(input);
    out.scene = loadGltfScene(input);  // names the file when it is missing or broken
    if (args.camera.empty())
      throw UserError("--camera: a glTF scene file needs a camera path (--camera FILE.json)");
    out.cameras = loadCameraJson(args.camera);
  } else {
    throw UserError("--suite: '" + input + "' does not exist or is not a scene folder or .gltf/.glb file");
  }
  for (Camera& c : out.cameras.frames) {
    if (args.fovy) c.fovy_degrees = *args.fovy;
    if (args.near_plane) c.near_plane = *args.near_plane;
    if (args.far_plane) c.far_plane = *args.far_plane;
  }
  if (args.resample > 0) out.cameras = resampleCameraPath(out.cameras, args.resample);
  return out;
}

std::vector<LightSetInput> resolveLightSets(const BenchScene& scene, const std::string& list,
                                            const BenchSceneArgs& args, const std::string& flag) {
  std::vector<std::string> items = splitList(list);
  if (items.empty()) {
    if (scene.default_lights.empty())
      throw UserError(flag + ": no light set given and the scene has no default light file");
    items = {scene.default_lights};
  }
  const bool suite = scene.format == "ntiled-suite";
  // A density applies to generated sets only: some item must be one.
  bool generates = false;
  for (const std::string& item : items) {
    std::uint32_t n = 0;
    generates |= !suite && parseCount(item, n);
  }
  checkLightDensityFlag(args.light_density, args.light_radius, generates);
  std::vector<LightSetInput> out;
  auto addFile = [&](const std::string& file) {
    LightSetInput s;
    s.file = reportPath(file);  // recorded in results: no machine paths
    s.label = stem(file);
    if (s.label == "lights" && !scene.name.empty()) s.label = scene.name + "/lights";
    s.lights = loadLightsJson(file);
    if (s.lights.empty()) throw UserError(file + ": the light set is empty");
    out.push_back(std::move(s));
  };
  for (const std::string& item : items) {
    std::uint32_t count = 0;
    if (item == "thesis" || item == "all") {
      if (!suite) throw UserError(flag + ": '" + item + "' needs a scene-suite folder (--suite)");
      const auto files = item == "all" ? scene.suite_light_files : thesisLightFiles(scene.suite_light_files);
      if (files.empty()) throw UserError(flag + ": the suite has no light files under " + scene.dir + "/lights");
      for (const auto& f : files) addFile(f);
    } else if (parseCount(item, count)) {
      if (suite) {
        std::string match;
        for (const auto& f : thesisLightFiles(scene.suite_light_files))
          if (lightCountFromFileName(f) == count) match = f;
        if (match.empty())
          throw UserError(flag + ": the suite has no light set with " + item + " lights (see " + scene.dir +
                          "/lights)");
        addFile(match);
        continue;
      }
      if (count == 0) throw UserError(flag + ": a generated light set needs at least one light");
      checkLightCount(flag, count, "generated");  // before any memory is spent on them
      std::string vol = args.light_volumes;
      if (vol.empty() && !scene.dir.empty() && fs::is_regular_file(fs::path(scene.dir) / "light_volumes.json"))
        vol = (fs::path(scene.dir) / "light_volumes.json").string();
      LightSetInput s;
      s.lights = generateLightsIn(vol, scene.scene.bounds.min, scene.scene.bounds.max, count, args.seed,
                                  args.light_radius, args.light_density);
      s.label = item + " generated" + densityLabel(args.light_density, s.lights);
      out.push_back(std::move(s));
    } else {
      std::string file = item;
      if (!fs::is_regular_file(file) && suite) {
        for (const fs::path& cand : {fs::path(scene.dir) / "lights" / item, fs::path(scene.dir) / "lights" / (item + ".json")})
          if (fs::is_regular_file(cand)) file = cand.string();
      }
      if (!fs::is_regular_file(file)) throw UserError(flag + ": light set '" + item + "' is not a file" +
                                                      (suite ? " (nor a name under " + scene.dir + "/lights)" : ""));
      addFile(file);
    }
  }
  return out;
}

}  // namespace ml
