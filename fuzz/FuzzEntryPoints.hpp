#pragma once
// What each fuzz target does with one input, shared by the libFuzzer harnesses
// (fuzz/fuzz_*.cpp) and the regression test that replays the inputs they
// found (tests/fuzz/fuzz_regression_test.cpp). Contract of every entry point: it
// returns normally or throws ml::UserError; anything else (another exception,
// a crash, a sanitizer report, a hang) is a bug of the loader it drives.
//
// The loaders read files, so the bytes go to files in a private temporary
// folder first (made once per process, removed at exit). Inputs that stand
// for several files (the suite target) are split on kFileSeparator lines; the
// command line is split into arguments on newlines and NULs.
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "host/cli/Cli.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/GltfLights.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"
#include "host/suite/CameraPathInterp.hpp"
#include "host/suite/NtiledSuite.hpp"
#include "host/suite/ThesisReference.hpp"
#include "host/util/Error.hpp"

namespace ml::fuzz {

namespace fs = std::filesystem;

inline constexpr std::string_view kFileSeparator = "\n#----\n";

// Removes the folder when the process ends (libFuzzer exits through exit()).
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "manylights-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

inline const fs::path& tempDir() {
  static TempDir dir;
  return dir.path;
}

inline std::string writeFile(const fs::path& path, std::string_view bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) std::abort();  // the harness's own folder: not the input's fault
  return path.string();
}

inline std::vector<std::string_view> split(std::string_view text, std::string_view sep) {
  std::vector<std::string_view> parts;
  for (std::size_t at = 0;;) {
    const std::size_t next = text.find(sep, at);
    parts.push_back(text.substr(at, next == std::string_view::npos ? std::string_view::npos : next - at));
    if (next == std::string_view::npos) return parts;
    at = next + sep.size();
  }
}

inline std::string_view view(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Loaded lights are what the renderer takes: finite, radius > 0, colour >= 0.
inline void checkLights(const std::vector<gpu::PointLight>& lights) {
  for (const gpu::PointLight& l : lights) {
    const float v[] = {l.position_radius.x, l.position_radius.y, l.position_radius.z, l.position_radius.w,
                       l.color.x,           l.color.y,           l.color.z};
    for (float f : v)
      if (!std::isfinite(f)) std::abort();
    if (!(l.position_radius.w > 0.0f) || l.color.x < 0.0f || l.color.y < 0.0f || l.color.z < 0.0f) std::abort();
  }
}

inline bool sameLights(const std::vector<gpu::PointLight>& a, const std::vector<gpu::PointLight>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

// .glb when the bytes start with the binary container's magic, else .gltf.
// The KHR_lights_punctual point lights are read alone (meshes ignored) and
// with the scene: the same lights, or an error from both; written back as
// glTF they must read back identical.
inline void gltf(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes = view(data, size);
  const bool glb = bytes.substr(0, 4) == "glTF";
  const std::string path = writeFile(tempDir() / (glb ? "scene.glb" : "scene.gltf"), bytes);
  bool lights_ok = true;
  GltfLightTable table;
  try {
    table = loadGltfLights(path);
  } catch (const UserError&) {
    lights_ok = false;
  }
  if (lights_ok) {
    checkLights(table.lights);
    const std::string copy = writeFile(tempDir() / (glb ? "lights.glb" : "lights.gltf"),
                                       gltfLightsDocument(table.lights, glb));
    if (!sameLights(loadGltfLights(copy).lights, table.lights)) std::abort();
  }
  const Scene scene = loadGltfScene(path);
  for (const std::uint32_t i : scene.indices)
    if (i >= scene.vertices.size()) std::abort();  // an index past the vertices would reach the GPU
  if (!lights_ok || !sameLights(scene.lights, table.lights)) std::abort();
}

// The same bytes as a light file and as a light-volume file; volumes that
// load then generate a few lights.
inline void lights(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeFile(tempDir() / "lights.json", view(data, size));
  bool lights_ok = true;
  try {
    (void)loadLightsJson(path);
  } catch (const UserError&) {
    lights_ok = false;
  }
  const LightVolumeSet set = loadLightVolumesJson(path);
  (void)generateLightsIn(path, glm::vec3(0.0f), glm::vec3(1.0f), 16, set.defaults.seed, 0.0f);
  if (!lights_ok) throw UserError(path + ": not a light file");
}

// Loads a camera or path, then derives what a render does: view, projection,
// kernel parameters, and a resampled path.
inline void camera(const std::uint8_t* data, std::size_t size) {
  const CameraPath path = loadCameraJson(writeFile(tempDir() / "camera.json", view(data, size)));
  for (const Camera& c : path.frames) (void)c.params(64, 48);
  const CameraPath resampled = resampleCameraPath(path, 5);
  (void)cameraAt(path, 0.5 * double(path.frames.size()));
  if (resampled.frames.size() != 5) std::abort();
}

// Parts: geometry JSON, mesh.obj, camera.json, a light file, lc_data.json.
inline void suite(const std::uint8_t* data, std::size_t size) {
  const fs::path dir = tempDir() / "suite";
  std::error_code ec;
  fs::remove_all(dir, ec);
  const auto parts = split(view(data, size), kFileSeparator);
  const char* names[] = {"geometry/deferred_attenuated.json", "obj/mesh.obj", "camera/camera.json",
                         "lights/70#1x_1y_1z.json", "lc_data.json"};
  for (std::size_t i = 0; i < parts.size() && i < std::size(names); ++i) writeFile(dir / names[i], parts[i]);
  if (parts.size() > 4) {
    try {
      (void)readLcData((dir / names[4]).string());
    } catch (const UserError&) {
    }
  }
  SuiteLoadOptions options;
  options.allow_missing_meshes = parts.size() > 5;
  const SuiteScene s = loadNtiledSuite(dir.string(), options);
  for (const std::uint32_t i : s.scene.indices)
    if (i >= s.scene.vertices.size()) std::abort();
  for (const auto& f : s.light_files) (void)loadLightsJson(f);
}

// argv[1..] from the input's lines (NULs split too), at most 64 arguments.
inline void cli(const std::uint8_t* data, std::size_t size) {
  std::string text(view(data, size));
  for (char& c : text)
    if (c == '\0') c = '\n';
  std::vector<std::string> args{"manylights"};
  for (const auto a : split(text, "\n"))
    if (args.size() < 65) args.emplace_back(a);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int code = parseCli(int(args.size()), argv.data());
  if (code != -1 && code != 0 && code != 2) std::abort();
}

}  // namespace ml::fuzz
