#include "host/scene/GltfModel.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "host/util/Error.hpp"

namespace ml::gltf_model {
namespace {

namespace fs = std::filesystem;

std::string oneLine(const std::string& text) {
  std::string out;
  bool pending_sep = false;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      pending_sep = !out.empty();
      continue;
    }
    if (pending_sep) out += "; ";
    pending_sep = false;
    out += c;
  }
  return out;
}

// tinygltf 2.7 passes a bufferView's bytes without checking them against its
// buffer: false (with a message) for a view outside it.
bool imageViewInBuffer(const tinygltf::Image& image, int image_idx, const tinygltf::Model* model, std::string* err) {
  if (!model || image.bufferView < 0) return true;
  const auto view = static_cast<std::size_t>(image.bufferView);
  bool ok = view < model->bufferViews.size();
  if (ok) {
    const tinygltf::BufferView& bv = model->bufferViews[view];
    ok = bv.buffer >= 0 && static_cast<std::size_t>(bv.buffer) < model->buffers.size();
    if (ok) {
      const std::size_t available = model->buffers[static_cast<std::size_t>(bv.buffer)].data.size();
      ok = bv.byteOffset <= available && bv.byteLength <= available - bv.byteOffset;
    }
  }
  if (!ok && err)
    *err += "image " + std::to_string(image_idx) + ": bufferView " + std::to_string(image.bufferView) +
            " lies outside its buffer\n";
  return ok;
}

// Wraps tinygltf's stb_image decoder. user_data is the Model being filled, whose
// buffers and bufferViews are already parsed when images are.
bool tolerantImageLoader(tinygltf::Image* image, const int image_idx, std::string* err, std::string* warn,
                         int req_width, int req_height, const unsigned char* bytes, int size, void* user) {
  if (!imageViewInBuffer(*image, image_idx, static_cast<const tinygltf::Model*>(user), err)) return false;
  // Without this a texture stb_image cannot decode fails the whole load inside
  // tinygltf; a scene is still useful with that material's base colour factor.
  std::string decode_err;
  if (tinygltf::LoadImageData(image, image_idx, &decode_err, warn, req_width, req_height, bytes, size, nullptr))
    return true;
  if (warn)
    *warn += "image " + std::to_string(image_idx) + " could not be decoded (" + oneLine(decode_err) +
             "); its textures are ignored\n";
  image->image.clear();
  return true;
}

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

}  // namespace

spdlog::logger& warnings() {
  // Not registered with spdlog: loading twice in one process (tests, fuzzing)
  // must not clash on the name.
  static spdlog::logger log("gltf", std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  return log;
}

std::string summarize(const std::string& text) {
  std::string out = oneLine(text);
  for (std::size_t at = out.find("data:"); at != std::string::npos; at = out.find("data:", at + 5)) {
    std::size_t end = at;
    while (end < out.size() && out[end] != ' ' && out[end] != '"' && out[end] != '\'' && out[end] != ';') ++end;
    if (end < out.size() && out[end] == ';') {  // skip ";base64,...." too
      while (end < out.size() && out[end] != ' ' && out[end] != '"' && out[end] != '\'') ++end;
    }
    if (end - at > 40) out.replace(at, end - at, "data:...");
  }
  constexpr std::size_t kMax = 400;
  if (out.size() > kMax) out = out.substr(0, kMax) + "...";
  return out;
}

tinygltf::Model readModel(const std::string& path, bool decode_images) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw UserError(path + ": file not found");
  if (!fs::is_regular_file(path, ec)) throw UserError(path + ": not a regular file");
  char magic[4] = {};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw UserError(path + ": cannot open file");
    in.read(magic, sizeof magic);
  }
  const bool binary = std::memcmp(magic, "glTF", 4) == 0;

  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  gltf.SetStoreOriginalJSONForExtrasAndExtensions(true);  // readLights checks the lights' JSON itself
  if (decode_images) gltf.SetImageLoader(&tolerantImageLoader, &model);
  else gltf.SetImageLoader(&skipImage, nullptr);
  std::string err, warn;
  bool ok = false;
  try {
    ok = binary ? gltf.LoadBinaryFromFile(&model, &err, &warn, path)
                : gltf.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {  // tinygltf lets some JSON type errors escape
    throw UserError(path + ": malformed glTF: " + summarize(e.what()));
  }
  if (!warn.empty()) warnings().warn("{}: {}", path, summarize(warn));
  if (!ok) {
    const std::string kind = binary ? "malformed .glb" : "malformed glTF";
    throw UserError(path + ": " + kind + (err.empty() ? std::string() : ": " + summarize(err)));
  }
  return model;
}

std::vector<int> sceneRoots(const tinygltf::Model& model, const std::string& path) {
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int which = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<std::size_t>(which) >= model.scenes.size())
      throw UserError(path + ": the default scene refers to scene " + std::to_string(which) +
                      ", which does not exist");
    return model.scenes[static_cast<std::size_t>(which)].nodes;
  }
  std::vector<char> is_child(model.nodes.size(), 0);
  for (const auto& n : model.nodes)
    for (int c : n.children)
      if (c >= 0 && static_cast<std::size_t>(c) < is_child.size()) is_child[static_cast<std::size_t>(c)] = 1;
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(static_cast<int>(i));
  return roots;
}

glm::mat4 localTransform(const tinygltf::Node& node, const std::string& path, const std::string& where) {
  auto fail = [&](const char* what) { throw UserError(path + ": " + where + " " + what); };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) fail("matrix must have 16 elements");
    glm::dmat4 m;
    std::memcpy(glm::value_ptr(m), node.matrix.data(), sizeof(double) * 16);  // both column-major
    return glm::mat4(m);
  }
  glm::dvec3 t(0.0), s(1.0);
  glm::dquat r(1.0, 0.0, 0.0, 0.0);
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) fail("translation must have 3 elements");
    t = {node.translation[0], node.translation[1], node.translation[2]};
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) fail("rotation must have 4 elements");
    // glTF stores (x, y, z, w); glm's constructor takes w first.
    r = glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) fail("scale must have 3 elements");
    s = {node.scale[0], node.scale[1], node.scale[2]};
  }
  glm::dmat4 m = glm::mat4_cast(r);
  m[0] *= s.x;
  m[1] *= s.y;
  m[2] *= s.z;
  m[3] = glm::dvec4(t, 1.0);
  return glm::mat4(m);
}

}  // namespace ml::gltf_model
