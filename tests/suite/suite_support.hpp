#pragma once
// A tiny scene suite in the thesis program's format, written by the tests
// themselves so the suite loader, `bench` and `compare-reference` are covered
// without the real thesis data:
//   obj/Wall.obj  a 20 x 20 quad in z = 0, no normals (the loader generates them)
//   obj/Tri.obj   one triangle (1,0,0) (0,1,0) (0,0,1), normals (0,0,1) given
//   geometry/deferred_attenuated.json
//       Wall.0 at (0,0,-10), no rotation: fills the view of every camera frame
//       Tri.0  at (10,0,0),  rotation (0, pi/2, 0)
//       Tri.1  at (0,20,0),  rotation (pi/2, pi/2, 0)   (tells the Euler order)
//       Gone.0 (only with_missing): a mesh whose .obj does not exist
//     mesh paths are absolute Windows paths, as in the published suite
//   lights/10#1x_1y_1z.json (10 lights in front of the wall), 20#1x_1y_2z.json
//     and 20#2x_1y_1z.json (20 lights; the thesis's set for 20 is the latter)
//   camera/camera.json: 3 frames at z = 0, 1, 2 looking down -z, up (0, 2, 0)
#include <numbers>
#include <filesystem>
#include <fstream>
#include <string>

namespace ml::test {

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

inline std::string suiteLightsJson(int count, float z) {
  std::string s = "{\"lights\": [";
  for (int i = 0; i < count; ++i) {
    const float x = -4.0f + 8.0f * static_cast<float>(i % 5) / 4.0f;
    const float y = -3.0f + 6.0f * static_cast<float>(i / 5 % 4) / 3.0f;
    s += std::string(i ? "," : "") + "{\"intensity\": {\"r\": 1.0, \"g\": 0.5, \"b\": 0.25}, \"position\": {\"x\": " +
         std::to_string(x) + ", \"y\": " + std::to_string(y) + ", \"z\": " + std::to_string(z) +
         "}, \"radius\": 3.0}";
  }
  return s + "]}\n";
}

// Returns the suite folder <root>/<name>.
inline std::string writeSmallSuite(const std::string& root, const std::string& name = "small-scene",
                                   bool with_missing = false) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(root) / name;
  writeText(dir / "obj" / "Wall.obj",
            "# quad, no normals\nv -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3\nf 1 3 4\n");
  writeText(dir / "obj" / "Tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1//1 2//1 3//1\n");
  const std::string hp = std::to_string(std::numbers::pi / 2);
  std::string objects =
      "{\"mesh_id\": \"Wall\", \"name\": \"Wall.0\", \"shader_id\": \"deferred_attenuated\", "
      "\"translation\": {\"x\": 0, \"y\": 0, \"z\": -10}, \"rotation\": {\"x\": 0, \"y\": 0, \"z\": -0.0}},"
      "{\"mesh_id\": \"Tri\", \"name\": \"Tri.0\", \"shader_id\": \"deferred_attenuated\", "
      "\"translation\": {\"z\": 0, \"y\": 0, \"x\": 10}, \"rotation\": {\"z\": 0, \"y\": " + hp + ", \"x\": 0}},"
      "{\"mesh_id\": \"Tri\", \"name\": \"Tri.1\", \"shader_id\": \"deferred_attenuated\", "
      "\"translation\": {\"x\": 0, \"y\": 20, \"z\": 0}, \"rotation\": {\"x\": " + hp + ", \"y\": " + hp + ", \"z\": 0}}";
  if (with_missing)
    objects += ",{\"mesh_id\": \"Gone\", \"name\": \"Gone.0\", \"shader_id\": \"deferred_attenuated\", "
               "\"translation\": {\"x\": 0, \"y\": 0, \"z\": 0}, \"rotation\": {\"x\": 0, \"y\": 0, \"z\": 0}}";
  writeText(dir / "geometry" / "deferred_attenuated.json",
            "{\"objects\": [" + objects +
                "], \"meshes\": [{\"id\": \"Wall\", \"path\": \"C:\\\\Users\\\\someone\\\\suite\\\\obj\\\\Wall.obj\"},"
                "{\"id\": \"Tri\", \"path\": \"C:\\\\Users\\\\someone\\\\suite\\\\obj\\\\Tri.obj\"},"
                "{\"id\": \"Gone\", \"path\": \"C:\\\\Users\\\\someone\\\\suite\\\\obj\\\\Gone.obj\"}]}\n");
  writeText(dir / "lights" / "10#1x_1y_1z.json", suiteLightsJson(10, -9.0f));
  writeText(dir / "lights" / "20#1x_1y_2z.json", suiteLightsJson(20, -8.5f));
  writeText(dir / "lights" / "20#2x_1y_1z.json", suiteLightsJson(20, -9.5f));
  std::string frames;
  for (int i = 0; i < 3; ++i)
    frames += std::string(i ? "," : "") + "{\"eye\": {\"x\": 0, \"y\": 0, \"z\": " + std::to_string(i) +
              "}, \"center\": {\"x\": 0, \"y\": 0, \"z\": " + std::to_string(i - 3) +
              "}, \"up\": {\"x\": 0, \"y\": 2.0, \"z\": 0}}";
  writeText(dir / "camera" / "camera.json", "{\"frames\": [" + frames + "]}\n");
  return dir.string();
}

}  // namespace ml::test
