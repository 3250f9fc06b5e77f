#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "host/scene/GltfModel.hpp"
#include "host/scene/Scene.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

using gltf_model::warnings;

struct Loader {
  const std::string& path;
  const tinygltf::Model& model;
  Scene& scene;

  std::vector<std::vector<std::uint32_t>> material_indices;  // triangles grouped by material
  std::map<int, int> image_to_texture;
  int default_material = -1;
  bool warned_texcoord = false;

  [[noreturn]] void fail(const std::string& what) const { throw UserError(path + ": " + what); }

  template <class T>
  const T& at(const std::vector<T>& list, int index, const char* kind, const std::string& where) const {
    if (index < 0 || static_cast<std::size_t>(index) >= list.size())
      fail(where + " refers to " + kind + " " + std::to_string(index) + ", which does not exist");
    return list[static_cast<std::size_t>(index)];
  }

  // A validated, strided view of one accessor's elements.
  struct View {
    const std::uint8_t* data = nullptr;  // null: all zeros (accessor without bufferView)
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
    int components = 0;
    bool normalized = false;
  };

  View view(int accessor_index, const std::string& where) const {
    const tinygltf::Accessor& acc = at(model.accessors, accessor_index, "accessor", where);
    const std::string me = "accessor " + std::to_string(accessor_index);
    if (acc.sparse.isSparse) fail(me + " is sparse, which is not supported");
    View v;
    v.count = acc.count;
    v.component_type = acc.componentType;
    v.components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
    v.normalized = acc.normalized;
    const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType));
    if (v.components <= 0 || component_size <= 0) fail(me + " has an invalid type or componentType");
    const std::size_t element = static_cast<std::size_t>(v.components) * static_cast<std::size_t>(component_size);
    if (acc.bufferView < 0) return v;

    const tinygltf::BufferView& bv = at(model.bufferViews, acc.bufferView, "bufferView", me);
    const tinygltf::Buffer& buf = at(model.buffers, bv.buffer, "buffer", "bufferView " + std::to_string(acc.bufferView));
    if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
      fail("bufferView " + std::to_string(acc.bufferView) + " extends past the end of buffer " +
           std::to_string(bv.buffer) + " (" + std::to_string(buf.data.size()) + " bytes)");
    v.stride = bv.byteStride ? bv.byteStride : element;
    if (v.stride < element) fail("bufferView " + std::to_string(acc.bufferView) + " has a byteStride below the element size");
    if (v.count > 0) {
      const std::size_t last = acc.byteOffset + (v.count - 1) * v.stride;
      const bool overflow = (v.count - 1) > (std::numeric_limits<std::size_t>::max() - acc.byteOffset) / v.stride;
      if (overflow || last > bv.byteLength || element > bv.byteLength - last)
        fail(me + " (" + std::to_string(v.count) + " elements) reads past the end of bufferView " +
             std::to_string(acc.bufferView) + " (" + std::to_string(bv.byteLength) + " bytes)");
    }
    v.data = buf.data.data() + bv.byteOffset + acc.byteOffset;
    return v;
  }

  template <class T>
  static T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof value);
    return value;
  }

  // Floats, or (normalised) integers as allowed by KHR_mesh_quantization.
  static float component(const View& v, std::size_t i, int c) {
    if (!v.data) return 0.0f;
    const std::uint8_t* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: return load<float>(p + 4 * c);
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const float x = load<std::int8_t>(p + c);
        return v.normalized ? std::max(x / 127.0f, -1.0f) : x;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        const float x = load<std::uint8_t>(p + c);
        return v.normalized ? x / 255.0f : x;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        const float x = load<std::int16_t>(p + 2 * c);
        return v.normalized ? std::max(x / 32767.0f, -1.0f) : x;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        const float x = load<std::uint16_t>(p + 2 * c);
        return v.normalized ? x / 65535.0f : x;
      }
      default: return 0.0f;  // rejected in floats()
    }
  }

  std::vector<float> floats(int accessor_index, int want_components, const std::string& where) const {
    const View v = view(accessor_index, where);
    if (v.components != want_components)
      fail(where + " needs a " + std::to_string(want_components) + "-component accessor, accessor " +
           std::to_string(accessor_index) + " has " + std::to_string(v.components));
    if (v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT || v.component_type == TINYGLTF_COMPONENT_TYPE_DOUBLE ||
        v.component_type == TINYGLTF_COMPONENT_TYPE_INT)
      fail(where + " uses accessor " + std::to_string(accessor_index) + " with an unsupported componentType");
    std::vector<float> out(v.count * static_cast<std::size_t>(want_components));
    for (std::size_t i = 0; i < v.count; ++i)
      for (int c = 0; c < want_components; ++c) out[i * want_components + c] = component(v, i, c);
    return out;
  }

  std::vector<std::uint32_t> indices(int accessor_index, std::size_t vertex_count, const std::string& where) const {
    const View v = view(accessor_index, where);
    if (v.components != 1) fail(where + " indices (accessor " + std::to_string(accessor_index) + ") must be SCALAR");
    std::vector<std::uint32_t> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) {
      const std::uint8_t* p = v.data ? v.data + i * v.stride : nullptr;
      std::uint32_t index = 0;
      switch (v.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: index = p ? load<std::uint8_t>(p) : 0; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: index = p ? load<std::uint16_t>(p) : 0; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: index = p ? load<std::uint32_t>(p) : 0; break;
        default: fail(where + " indices (accessor " + std::to_string(accessor_index) + ") must be unsigned integers");
      }
      if (index >= vertex_count)
        fail(where + " index " + std::to_string(index) + " is out of range (" + std::to_string(vertex_count) +
             " vertices)");
      out[i] = index;
    }
    return out;
  }

  int materialFor(int gltf_material, const std::string& where) {
    if (gltf_material >= 0) {
      at(model.materials, gltf_material, "material", where);
      return gltf_material;
    }
    if (default_material < 0) {
      default_material = static_cast<int>(scene.materials.size());
      scene.materials.push_back(Material{});
      material_indices.emplace_back();
    }
    return default_material;
  }

  int textureFor(int gltf_texture, const std::string& where) {
    const tinygltf::Texture& tex = at(model.textures, gltf_texture, "texture", where);
    if (tex.source < 0) return -1;  // e.g. only an extension source we do not read
    const tinygltf::Image& img = at(model.images, tex.source, "image", "texture " + std::to_string(gltf_texture));
    if (auto it = image_to_texture.find(tex.source); it != image_to_texture.end()) return it->second;

    int result = -1;
    const std::size_t pixels = img.width > 0 && img.height > 0
                                   ? static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height)
                                   : 0;
    const int bytes_per_channel = img.bits == 16 ? 2 : 1;
    if (pixels == 0 || img.component < 1 || img.component > 4 || (img.bits != 8 && img.bits != 16) ||
        img.image.size() < pixels * static_cast<std::size_t>(img.component * bytes_per_channel)) {
      warnings().warn("{}: image {} has no usable pixel data; materials using it fall back to their base colour", path,
                   tex.source);
    } else {
      Texture t;
      t.width = img.width;
      t.height = img.height;
      t.rgba8.resize(pixels * 4);
      const int comps = img.component;
      for (std::size_t i = 0; i < pixels; ++i) {
        std::uint8_t ch[4] = {0, 0, 0, 255};
        for (int c = 0; c < comps; ++c) {
          const std::size_t at_byte = (i * comps + c) * bytes_per_channel;
          // 16-bit PNGs arrive as native-endian uint16: keep the high byte.
          ch[c] = bytes_per_channel == 2 ? static_cast<std::uint8_t>(load<std::uint16_t>(&img.image[at_byte]) >> 8)
                                         : img.image[at_byte];
        }
        if (comps == 1 || comps == 2) {  // grey (+ alpha)
          const std::uint8_t alpha = comps == 2 ? ch[1] : 255;
          ch[1] = ch[2] = ch[0];
          ch[3] = alpha;
        }
        std::memcpy(&t.rgba8[i * 4], ch, 4);
      }
      result = static_cast<int>(scene.textures.size());
      scene.textures.push_back(std::move(t));
    }
    image_to_texture[tex.source] = result;
    return result;
  }

  void convertMaterials() {
    for (std::size_t i = 0; i < model.materials.size(); ++i) {
      const tinygltf::Material& m = model.materials[i];
      const std::string where = "material " + std::to_string(i);
      Material out;
      const auto& factor = m.pbrMetallicRoughness.baseColorFactor;
      if (factor.size() == 4) {
        out.base_color = glm::vec4(factor[0], factor[1], factor[2], factor[3]);
        if (!std::isfinite(out.base_color.r) || !std::isfinite(out.base_color.g) ||
            !std::isfinite(out.base_color.b) || !std::isfinite(out.base_color.a))
          fail(where + " has a non-finite baseColorFactor");
      } else if (!factor.empty()) {
        fail(where + " baseColorFactor must have 4 elements");
      }
      const auto& info = m.pbrMetallicRoughness.baseColorTexture;
      if (info.index >= 0) {
        out.base_color_texture = textureFor(info.index, where);
        if (info.texCoord != 0 && !warned_texcoord) {
          warnings().warn("{}: {} samples its base colour with TEXCOORD_{}; only TEXCOORD_0 is loaded", path, where,
                       info.texCoord);
          warned_texcoord = true;
        }
      }
      scene.materials.push_back(out);
      material_indices.emplace_back();
    }
  }

  // A primitive's vertex attributes; normals and uvs empty when it has none.
  struct Attributes {
    std::vector<float> positions, normals, uvs;
    std::size_t count() const { return positions.size() / 3; }
  };

  Attributes attributes(const tinygltf::Primitive& prim, int position_accessor, const std::string& where) const {
    Attributes a;
    a.positions = floats(position_accessor, 3, where + " POSITION");
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      a.normals = floats(it->second, 3, where + " NORMAL");
      if (a.normals.size() != a.positions.size()) fail(where + " NORMAL and POSITION counts differ");
    }
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      a.uvs = floats(it->second, 2, where + " TEXCOORD_0");
      if (a.uvs.size() / 2 != a.count()) fail(where + " TEXCOORD_0 and POSITION counts differ");
    }
    return a;
  }

  // Three vertex indices per triangle of a triangle list, strip or fan over
  // n vertices (indexed or not); strips keep their winding.
  std::vector<std::uint32_t> triangles(const tinygltf::Primitive& prim, int mode, std::size_t n,
                                       const std::string& where) const {
    std::vector<std::uint32_t> order;
    if (prim.indices >= 0) {
      order = indices(prim.indices, n, where);
    } else {
      order.resize(n);
      for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::uint32_t> tris;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      tris.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(order.size() / 3 * 3));
    } else if (order.size() >= 3) {
      for (std::size_t i = 0; i + 2 < order.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)  // every other triangle reversed to keep the winding
          tris.insert(tris.end(), {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
        else
          tris.insert(tris.end(), {order[i + 1], order[i + 2], order[0]});
      }
    }
    return tris;
  }

  // Appends the primitive's vertices in world space; returns the first one's index.
  std::uint32_t appendVertices(const Attributes& a, const glm::mat4& world, const std::string& where) {
    const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(world));
    const std::size_t n = a.count();
    if (scene.vertices.size() + n > std::numeric_limits<std::uint32_t>::max()) fail("too many vertices for 32-bit indices");
    const auto base = static_cast<std::uint32_t>(scene.vertices.size());
    for (std::size_t i = 0; i < n; ++i) {
      Vertex v;
      v.position = glm::vec3(world * glm::vec4(a.positions[3 * i], a.positions[3 * i + 1], a.positions[3 * i + 2], 1.0f));
      if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z))
        fail(where + " has a non-finite vertex position");
      v.normal = a.normals.empty()
                     ? glm::vec3(0.0f)
                     : normal_matrix * glm::vec3(a.normals[3 * i], a.normals[3 * i + 1], a.normals[3 * i + 2]);
      v.uv = a.uvs.empty() ? glm::vec2(0.0f) : glm::vec2(a.uvs[2 * i], a.uvs[2 * i + 1]);
      scene.vertices.push_back(v);
      scene.bounds.extend(v.position);
    }
    return base;
  }

  // Normalises the normals of the n vertices from `base`; missing and
  // degenerate ones become area-weighted face normals (the unnormalised cross
  // product is twice the area).
  void finishNormals(std::uint32_t base, std::size_t n, const std::vector<std::uint32_t>& tris) {
    std::vector<glm::vec3> generated;
    for (std::size_t i = 0; i < n; ++i) {
      Vertex& v = scene.vertices[base + i];
      const float len = glm::length(v.normal);
      if (len > 1e-20f && std::isfinite(len)) {
        v.normal /= len;
        continue;
      }
      if (generated.empty()) {
        generated.assign(n, glm::vec3(0.0f));
        for (std::size_t t = 0; t < tris.size(); t += 3) {
          const glm::vec3& a = scene.vertices[base + tris[t]].position;
          const glm::vec3& b = scene.vertices[base + tris[t + 1]].position;
          const glm::vec3& c = scene.vertices[base + tris[t + 2]].position;
          const glm::vec3 face = glm::cross(b - a, c - a);
          for (int k = 0; k < 3; ++k) generated[tris[t + k]] += face;
        }
      }
      const float glen = glm::length(generated[i]);
      v.normal = glen > 0.0f ? generated[i] / glen : glm::vec3(0.0f, 1.0f, 0.0f);
    }
  }

  void addPrimitive(const tinygltf::Primitive& prim, const glm::mat4& world, const std::string& where) {
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warnings().warn("{}: {} has mode {} (points or lines); skipped", path, where, mode);
      return;
    }
    auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) {
      warnings().warn("{}: {} has no POSITION attribute; skipped", path, where);
      return;
    }
    const Attributes attrs = attributes(prim, pos_it->second, where);
    std::vector<std::uint32_t> tris = triangles(prim, mode, attrs.count(), where);
    if (tris.empty()) return;

    const float det = glm::determinant(glm::mat3(world));
    if (!(std::abs(det) > 1e-20f) || !std::isfinite(det)) {
      warnings().warn("{}: {} has a singular or non-finite transform; skipped", path, where);
      return;
    }
    // A mirroring transform turns counter-clockwise triangles clockwise.
    if (det < 0.0f)
      for (std::size_t t = 0; t < tris.size(); t += 3) std::swap(tris[t + 1], tris[t + 2]);
    const std::uint32_t base = appendVertices(attrs, world, where);
    finishNormals(base, attrs.count(), tris);

    const int material = materialFor(prim.material, where);
    auto& dst = material_indices[static_cast<std::size_t>(material)];
    for (std::uint32_t idx : tris) dst.push_back(base + idx);
  }

  void visit(int node_index, const glm::mat4& parent, std::vector<char>& on_path, int depth) {
    const tinygltf::Node& node = at(model.nodes, node_index, "node", depth == 0 ? "the scene" : "a node");
    const std::string where = "node " + std::to_string(node_index);
    if (on_path[static_cast<std::size_t>(node_index)]) fail(where + " is its own ancestor");
    on_path[static_cast<std::size_t>(node_index)] = 1;
    const glm::mat4 world = parent * gltf_model::localTransform(node, path, where);
    if (node.mesh >= 0) {
      const tinygltf::Mesh& mesh = at(model.meshes, node.mesh, "mesh", where);
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
        addPrimitive(mesh.primitives[p], world,
                     "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p) + " (" + where + ")");
    }
    for (int child : node.children) visit(child, world, on_path, depth + 1);
    on_path[static_cast<std::size_t>(node_index)] = 0;
  }

  void run() {
    convertMaterials();
    const std::vector<int> roots = gltf_model::sceneRoots(model, path);
    std::vector<char> on_path(model.nodes.size(), 0);
    for (int root : roots) visit(root, glm::mat4(1.0f), on_path, 0);

    for (std::size_t m = 0; m < material_indices.size(); ++m) {
      const auto& list = material_indices[m];
      if (list.empty()) continue;
      DrawBatch batch;
      batch.first_index = static_cast<std::uint32_t>(scene.indices.size());
      batch.index_count = static_cast<std::uint32_t>(list.size());
      batch.material = static_cast<std::uint32_t>(m);
      scene.indices.insert(scene.indices.end(), list.begin(), list.end());
      scene.batches.push_back(batch);
    }
    if (scene.indices.empty()) fail("no triangles found (only empty, point or line primitives)");
  }
};

}  // namespace

Scene loadGltfScene(const std::string& path, float light_threshold) {
  const tinygltf::Model model = gltf_model::readModel(path, true);
  Scene scene;
  scene.source = path;
  Loader loader{path, model, scene, {}, {}, -1, false};
  loader.run();
  GltfLightTable lights = gltf_model::readLights(model, path, light_threshold);
  if (const std::string note = lights.skippedNote(); !note.empty()) warnings().warn("{}: {}", path, note);
  scene.lights = std::move(lights.lights);
  return scene;
}

}  // namespace ml
