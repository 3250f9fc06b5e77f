#pragma once
// Loader for the scene-suite format of the hashed-shading thesis's program
// (nTiled), as published in its data repository:
//
//   <dir>/geometry/<pipeline>_<technique>.json  {"meshes": [{"id", "path"}],
//                                                "objects": [{"mesh_id", "name",
//                                                  "translation": {x,y,z},
//                                                  "rotation": {x,y,z} (radians),
//                                                  "shader_id"}]}
//   <dir>/obj/<mesh>.obj                         meshes (Wavefront OBJ)
//   <dir>/lights/<count>#<ax>x_<ay>y_<az>z.json  point lights
//   <dir>/camera/camera.json                     {"frames": [{eye, center, up}]}
//
// Object transform, as nTiled's GeometryParser builds it with glm::rotate
// (each call post-multiplies): M = T(translation) * Rx(x) * Ry(y) * Rz(z), so a
// vertex is rotated about z first, then y, then x, then translated. Mesh
// paths in the geometry file are the author's absolute Windows paths; only
// their file name is used, looked up in <dir>/obj/ (then <dir>/obj/<id>.obj).
// The result is flattened to one world-space ml::Scene with a single white
// material (the thesis shades white Lambertian surfaces only).
#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

// The camera settings of every configuration the thesis ran on its suite.
struct SuiteCameraSettings {
  float fovy_degrees = 45.0f;
  float aspect = 1.0f;  // the thesis renders square viewports
  float near_plane = 0.01f;
  float far_plane = 4000.0f;
};

struct SuiteLoadOptions {
  // A file under geometry/ (name or path); empty: deferred_attenuated.json if
  // present, else the first geometry file by name. All of a scene's geometry
  // files place the same objects; they differ only in shader_id.
  std::string geometry;
  // Skip objects whose mesh file is missing (with a warning) instead of
  // failing. The published spaceship-indoor copy lacks Junction-4.obj.
  bool allow_missing_meshes = false;
  SuiteCameraSettings camera;
};

struct SuiteObject {
  std::string mesh_id;
  std::string name;
  glm::vec3 translation{0.0f};
  glm::vec3 rotation{0.0f};  // Euler angles in radians, applied z, y, x (see above)
};

struct SuiteScene {
  std::string dir;
  std::string name;           // the folder's name, e.g. "spaceship-indoor"
  std::string geometry_file;  // the geometry JSON actually read
  Scene scene;                // world space, one white material
  CameraPath cameras;         // camera.json with `camera` settings applied to every frame
  SuiteCameraSettings camera;
  std::vector<std::string> light_files;     // lights/*.json, by light count then name
  std::vector<SuiteObject> objects;         // as listed (missing meshes included)
  std::vector<std::string> missing_meshes;  // mesh ids skipped (allow_missing_meshes)
  std::size_t placed_objects = 0;           // objects whose mesh was found
};

// True if `dir` looks like a suite scene folder (has geometry/ and camera/camera.json).
bool isNtiledSuiteDir(const std::string& dir);

// M = T * Rx * Ry * Rz, exactly as nTiled composes it.
glm::mat4 ntiledObjectTransform(const glm::vec3& translation, const glm::vec3& rotation_radians);

// Parses a geometry JSON file (objects and the mesh id -> path table).
// Throws UserError naming the file for unreadable or malformed input.
struct SuiteGeometry {
  std::vector<std::pair<std::string, std::string>> meshes;  // id -> path as written
  std::vector<SuiteObject> objects;
};
SuiteGeometry parseSuiteGeometry(const std::string& path);

// Loads the whole folder. Throws UserError naming the file or folder that is
// missing or malformed; a missing mesh names the .obj it looked for and the
// flag that skips it.
SuiteScene loadNtiledSuite(const std::string& dir, const SuiteLoadOptions& options = {});

// Light files of a suite folder, sorted by light count then name.
std::vector<std::string> suiteLightFiles(const std::string& dir);
// "70#1x_1y_1z.json" -> 70; 0 when the name does not start with a count.
unsigned lightCountFromFileName(const std::string& path);
// The light sets the thesis measured per light count: for each count, the
// file name that sorts last (70#1x_1y_1z, 140#2x_1y_1z, 210#3x_1y_1z, ...,
// 1260#3x_3y_2z, 1890#3x_3y_3z; these are the sets under the thesis's
// reference/light_calculations/lights/).
std::vector<std::string> thesisLightFiles(const std::vector<std::string>& light_files);

}  // namespace ml
