#include "host/suite/NtiledSuite.hpp"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <spdlog/spdlog.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <unordered_map>

#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

using scene_json::json;

// A mesh as loaded once and instanced by every object that names it.
struct ObjMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // unit length, one per position
  std::vector<std::uint32_t> triangles;
};

std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

void readObj(const std::string& path, tinyobj::ObjReader& reader) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = fs::path(path).parent_path().string();
  if (!reader.ParseFromFile(path, config))
    throw UserError(path + ": cannot read OBJ mesh: " + oneLine(reader.Error().empty() ? "unknown error" : reader.Error()));
}

glm::vec3 objPosition(const tinyobj::attrib_t& attrib, int i) {
  return glm::vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
}

bool hasNormal(const tinyobj::attrib_t& attrib, const tinyobj::index_t& corner) {
  return corner.normal_index >= 0 && static_cast<std::size_t>(corner.normal_index) < attrib.normals.size() / 3;
}

// Per input position, the sum of its faces' area-weighted normals, for the
// corners that have no normal of their own; empty when every corner has one.
std::vector<glm::vec3> smoothNormals(const tinyobj::ObjReader& reader) {
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::size_t nv = attrib.vertices.size() / 3;
  bool need_smooth = false;
  for (const auto& shape : reader.GetShapes())
    for (const auto& idx : shape.mesh.indices)
      if (!hasNormal(attrib, idx)) need_smooth = true;
  if (!need_smooth) return {};
  std::vector<glm::vec3> smooth(nv, glm::vec3(0.0f));
  for (const auto& shape : reader.GetShapes()) {
    const auto& ix = shape.mesh.indices;
    for (std::size_t t = 0; t + 2 < ix.size(); t += 3) {
      const int a = ix[t].vertex_index, b = ix[t + 1].vertex_index, c = ix[t + 2].vertex_index;
      // Faces past the vertices are refused by loadObj; skip them here (found by fuzzing).
      auto bad = [&](int i) { return i < 0 || static_cast<std::size_t>(i) >= nv; };
      if (bad(a) || bad(b) || bad(c)) continue;
      const glm::vec3 face =
          glm::cross(objPosition(attrib, b) - objPosition(attrib, a), objPosition(attrib, c) - objPosition(attrib, a));
      smooth[a] += face;
      smooth[b] += face;
      smooth[c] += face;
    }
  }
  return smooth;
}

ObjMesh loadObj(const std::string& path) {
  tinyobj::ObjReader reader;
  readObj(path, reader);
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::size_t nv = attrib.vertices.size() / 3;

  // One output vertex per distinct (position, normal) pair; corners without a
  // normal share a smooth, area-weighted normal of their position.
  ObjMesh mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> remap;
  const std::vector<glm::vec3> smooth = smoothNormals(reader);
  for (const auto& shape : reader.GetShapes()) {
    const auto& ix = shape.mesh.indices;
    for (std::size_t t = 0; t + 2 < ix.size(); t += 3) {
      std::uint32_t tri[3];
      for (int k = 0; k < 3; ++k) {
        const auto& c = ix[t + k];
        if (c.vertex_index < 0 || static_cast<std::size_t>(c.vertex_index) >= nv)
          throw UserError(path + ": face refers to a vertex that does not exist");
        const bool has_n = hasNormal(attrib, c);
        const std::uint64_t key = (static_cast<std::uint64_t>(c.vertex_index) << 32) |
                                  static_cast<std::uint32_t>(has_n ? c.normal_index : -1);
        auto [it, fresh] = remap.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
        if (fresh) {
          mesh.positions.push_back(objPosition(attrib, c.vertex_index));
          glm::vec3 n = has_n ? glm::vec3(attrib.normals[3 * c.normal_index], attrib.normals[3 * c.normal_index + 1],
                                          attrib.normals[3 * c.normal_index + 2])
                              : smooth[static_cast<std::size_t>(c.vertex_index)];
          const float len = glm::length(n);
          n = (len > 1e-20f && std::isfinite(len)) ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
          mesh.normals.push_back(n);
        }
        tri[k] = it->second;
      }
      mesh.triangles.insert(mesh.triangles.end(), tri, tri + 3);
    }
  }
  if (mesh.triangles.empty()) throw UserError(path + ": OBJ mesh has no faces");
  return mesh;
}

// "C:\\Users\\...\\obj\\PanelB.obj" -> "PanelB.obj" (either separator).
std::string fileNameOf(const std::string& p) {
  const auto cut = p.find_last_of("/\\");
  return cut == std::string::npos ? p : p.substr(cut + 1);
}

std::string chooseGeometryFile(const std::string& dir, const std::string& wanted) {
  const fs::path gdir = fs::path(dir) / "geometry";
  if (!wanted.empty()) {
    for (const fs::path& p : {fs::path(wanted), gdir / wanted, gdir / (wanted + ".json")})
      if (fs::is_regular_file(p)) return p.string();
    throw UserError("--geometry: no geometry file '" + wanted + "' (looked in " + gdir.string() + ")");
  }
  if (fs::is_regular_file(gdir / "deferred_attenuated.json")) return (gdir / "deferred_attenuated.json").string();
  std::vector<std::string> all;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(gdir, ec))
    if (e.is_regular_file() && e.path().extension() == ".json") all.push_back(e.path().string());
  if (all.empty()) throw UserError(gdir.string() + ": no geometry JSON files in the suite folder");
  std::sort(all.begin(), all.end());
  return all.front();
}

}  // namespace

bool isNtiledSuiteDir(const std::string& dir) {
  std::error_code ec;
  return fs::is_directory(fs::path(dir) / "geometry", ec) && fs::is_regular_file(fs::path(dir) / "camera" / "camera.json", ec);
}

glm::mat4 ntiledObjectTransform(const glm::vec3& translation, const glm::vec3& rotation) {
  glm::mat4 r(1.0f);
  r = glm::rotate(r, rotation.x, glm::vec3(1.0f, 0.0f, 0.0f));
  r = glm::rotate(r, rotation.y, glm::vec3(0.0f, 1.0f, 0.0f));
  r = glm::rotate(r, rotation.z, glm::vec3(0.0f, 0.0f, 1.0f));
  return glm::translate(glm::mat4(1.0f), translation) * r;
}

SuiteGeometry parseSuiteGeometry(const std::string& path) {
  const json doc = scene_json::readFile(path, "geometry");
  if (!doc.is_object()) throw UserError(path + ": geometry file needs a top-level object");
  SuiteGeometry g;
  if (auto it = doc.find("meshes"); it != doc.end()) {
    if (!it->is_array()) throw UserError(path + ": \"meshes\" must be an array");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& m = (*it)[i];
      const std::string where = path + ": mesh " + std::to_string(i);
      if (!m.is_object() || !m.contains("id") || !m["id"].is_string())
        throw UserError(where + ": needs a string \"id\"");
      const std::string p = m.contains("path") && m["path"].is_string() ? m["path"].get<std::string>() : "";
      g.meshes.emplace_back(m["id"].get<std::string>(), p);
    }
  }
  const json& objects = scene_json::member(doc, "objects", path);
  if (!objects.is_array()) throw UserError(path + ": \"objects\" must be an array");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const json& o = objects[i];
    const std::string where = path + ": object " + std::to_string(i);
    if (!o.is_object()) throw UserError(where + ": must be an object");
    const json& id = scene_json::member(o, "mesh_id", where);
    if (!id.is_string()) throw UserError(where + ": \"mesh_id\" must be a string");
    SuiteObject so;
    so.mesh_id = id.get<std::string>();
    so.name = o.contains("name") && o["name"].is_string() ? o["name"].get<std::string>() : so.mesh_id;
    if (auto t = o.find("translation"); t != o.end()) so.translation = scene_json::toVec3(*t, where, "translation");
    if (auto r = o.find("rotation"); r != o.end()) so.rotation = scene_json::toVec3(*r, where, "rotation");
    g.objects.push_back(std::move(so));
  }
  return g;
}

unsigned lightCountFromFileName(const std::string& path) {
  const std::string name = fileNameOf(path);
  unsigned n = 0;
  std::size_t i = 0;
  for (; i < name.size() && name[i] >= '0' && name[i] <= '9' && n < 100000000u; ++i) n = n * 10 + unsigned(name[i] - '0');
  return i > 0 && i < name.size() && name[i] == '#' ? n : 0;
}

std::vector<std::string> suiteLightFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(dir) / "lights", ec))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    const unsigned na = lightCountFromFileName(a), nb = lightCountFromFileName(b);
    return na != nb ? na < nb : fileNameOf(a) < fileNameOf(b);
  });
  return files;
}

std::vector<std::string> thesisLightFiles(const std::vector<std::string>& light_files) {
  std::map<unsigned, std::string> last;
  for (const auto& f : light_files) {
    const unsigned n = lightCountFromFileName(f);
    if (n == 0) continue;
    auto it = last.find(n);
    if (it == last.end() || fileNameOf(it->second) < fileNameOf(f)) last[n] = f;
  }
  std::vector<std::string> out;
  for (const auto& [n, f] : last) out.push_back(f);
  return out;
}

namespace {

// Where a mesh id's OBJ file is: the path the geometry file declares for it,
// by its file name under obj/ or as written, else obj/<id>.obj.
class MeshFiles {
 public:
  MeshFiles(const std::string& dir, const SuiteGeometry& geo)
      : obj_dir_(fs::path(dir) / "obj"), declared_(geo.meshes.begin(), geo.meshes.end()) {}
  fs::path operator()(const std::string& id) const {
    if (auto it = declared_.find(id); it != declared_.end() && !it->second.empty()) {
      const fs::path by_name = obj_dir_ / fileNameOf(it->second);
      if (fs::is_regular_file(by_name)) return by_name;
      if (fs::is_regular_file(it->second)) return it->second;  // a usable path as written
    }
    return obj_dir_ / (id + ".obj");
  }

 private:
  fs::path obj_dir_;
  std::map<std::string, std::string> declared_;
};

// Appends one instance of `m` placed by `o` to the scene; a mirroring
// transform gets its triangles' winding turned back.
void placeMesh(Scene& scene, const ObjMesh& m, const SuiteObject& o, const std::string& geometry_file) {
  const glm::mat4 world = ntiledObjectTransform(o.translation, o.rotation);
  const glm::mat3 linear(world);
  const glm::mat3 normal_matrix = glm::inverseTranspose(linear);
  const bool mirrored = glm::determinant(linear) < 0.0f;
  if (scene.vertices.size() + m.positions.size() > std::numeric_limits<std::uint32_t>::max())
    throw UserError(geometry_file + ": too many vertices for 32-bit indices");
  const auto base = static_cast<std::uint32_t>(scene.vertices.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    Vertex v;
    v.position = glm::vec3(world * glm::vec4(m.positions[i], 1.0f));
    v.normal = glm::normalize(normal_matrix * m.normals[i]);
    v.uv = glm::vec2(0.0f);
    scene.vertices.push_back(v);
    scene.bounds.extend(v.position);
  }
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    scene.indices.push_back(base + m.triangles[t]);
    scene.indices.push_back(base + m.triangles[t + (mirrored ? 2 : 1)]);
    scene.indices.push_back(base + m.triangles[t + (mirrored ? 1 : 2)]);
  }
}

// Places every object of `geo` in out.scene, loading each mesh once. A
// missing mesh is refused, or with allow_missing_meshes skipped, listed in
// out.missing_meshes and warned about once.
void placeObjects(SuiteScene& out, const SuiteGeometry& geo, const SuiteLoadOptions& options) {
  const MeshFiles meshFile(out.dir, geo);
  std::map<std::string, ObjMesh> meshes;
  std::map<std::string, std::size_t> missing_uses;
  for (const SuiteObject& o : geo.objects) {
    auto it = meshes.find(o.mesh_id);
    if (it == meshes.end()) {
      if (missing_uses.count(o.mesh_id)) {
        ++missing_uses[o.mesh_id];
        continue;
      }
      const fs::path file = meshFile(o.mesh_id);
      if (!fs::is_regular_file(file)) {
        if (!options.allow_missing_meshes)
          throw UserError(file.string() + ": mesh '" + o.mesh_id + "' (used by object '" + o.name + "' in " +
                          out.geometry_file + ") is missing; pass --allow-missing-meshes to render without it");
        missing_uses[o.mesh_id] = 1;
        continue;
      }
      it = meshes.emplace(o.mesh_id, loadObj(file.string())).first;
    }
    placeMesh(out.scene, it->second, o, out.geometry_file);
    ++out.placed_objects;
  }
  for (const auto& [id, uses] : missing_uses) {
    out.missing_meshes.push_back(id);
    spdlog::warn("{}: mesh '{}' is missing ({} object(s) skipped, --allow-missing-meshes); frames that see it "
                 "will differ from the thesis's",
                 meshFile(id).string(), id, uses);
  }
}

// The suite's camera path, every frame with the lens of out.camera.
void loadSuiteCameras(SuiteScene& out) {
  const std::string cam_file = (fs::path(out.dir) / "camera" / "camera.json").string();
  out.cameras = loadCameraJson(cam_file);
  for (Camera& c : out.cameras.frames) {
    c.fovy_degrees = out.camera.fovy_degrees;
    c.near_plane = out.camera.near_plane;
    c.far_plane = out.camera.far_plane;
  }
}

}  // namespace

SuiteScene loadNtiledSuite(const std::string& dir, const SuiteLoadOptions& options) {
  if (!fs::is_directory(dir)) throw UserError("--suite: '" + dir + "' is not a folder");
  if (!isNtiledSuiteDir(dir))
    throw UserError(dir + ": not a scene-suite folder (needs geometry/*.json and camera/camera.json)");
  SuiteScene out;
  out.dir = dir;
  out.name = fs::path(dir).lexically_normal().filename().string();
  if (out.name.empty()) out.name = fs::path(dir).lexically_normal().parent_path().filename().string();
  out.camera = options.camera;
  out.geometry_file = chooseGeometryFile(dir, options.geometry);
  SuiteGeometry geo = parseSuiteGeometry(out.geometry_file);
  out.objects = geo.objects;
  if (geo.objects.empty()) throw UserError(out.geometry_file + ": no objects");

  Scene& scene = out.scene;
  scene.source = dir;
  placeObjects(out, geo, options);
  if (scene.indices.empty()) throw UserError(dir + ": no geometry could be loaded");
  scene.materials = {Material{}};
  scene.batches = {DrawBatch{0, static_cast<std::uint32_t>(scene.indices.size()), 0}};
  loadSuiteCameras(out);
  out.light_files = suiteLightFiles(dir);
  return out;
}

}  // namespace ml
