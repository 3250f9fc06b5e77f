// glTF loading: a small scene written by the test itself (so every expected
// number is derived here by hand, independently of the loader), malformed
// inputs, and the shipped default scene.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/scene/Scene.hpp"
#include "host/util/Error.hpp"
#include "support/FileErrors.hpp"

#include "support/TempDir.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using ml::test::TempDir;

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string base64(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], table[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {table[v >> 18], table[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
  }
  return out;
}

std::uint32_t crc32(const std::string& data) {
  std::uint32_t crc = 0xffffffffu;
  for (unsigned char c : data) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string be32(std::uint32_t v) {
  return {char(v >> 24), char((v >> 16) & 255), char((v >> 8) & 255), char(v & 255)};
}

// RGBA8 PNG with an uncompressed ("stored") deflate stream: no zlib needed.
std::string pngRgba(int w, int h, const std::vector<std::uint8_t>& rgba) {
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw += '\0';
    raw.append(reinterpret_cast<const char*>(&rgba[std::size_t(y) * w * 4]), std::size_t(w) * 4);
  }
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  const auto len = static_cast<std::uint16_t>(raw.size());
  std::string z = "\x78\x01";
  z += '\x01';
  z += {char(len & 255), char(len >> 8), char(~len & 255), char((~len >> 8) & 255)};
  z += raw + be32(b << 16 | a);
  auto chunk = [](const std::string& tag, const std::string& data) {
    return be32(static_cast<std::uint32_t>(data.size())) + tag + data + be32(crc32(tag + data));
  };
  std::string ihdr = be32(w) + be32(h) + std::string("\x08\x06\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", z) + chunk("IEND", "");
}

// Binary payload + bufferViews + accessors, built up one attribute at a time.
struct GltfBuilder {
  std::string bin;
  json doc = json::object();

  GltfBuilder() {
    doc["asset"] = {{"version", "2.0"}};
    doc["bufferViews"] = json::array();
    doc["accessors"] = json::array();
  }
  int view(const std::string& bytes) {
    while (bin.size() % 4) bin += '\0';
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
    bin += bytes;
    return int(doc["bufferViews"].size()) - 1;
  }
  int accessor(const std::string& bytes, int component_type, std::size_t count, const char* type) {
    doc["accessors"].push_back(
        {{"bufferView", view(bytes)}, {"componentType", component_type}, {"count", count}, {"type", type}});
    return int(doc["accessors"].size()) - 1;
  }
  int vec3(const std::vector<glm::vec3>& v) {
    std::string b(v.size() * 12, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    int idx = accessor(b, 5126, v.size(), "VEC3");
    glm::vec3 mn(1e30f), mx(-1e30f);
    for (auto& p : v) mn = glm::min(mn, p), mx = glm::max(mx, p);
    doc["accessors"][idx]["min"] = {mn.x, mn.y, mn.z};
    doc["accessors"][idx]["max"] = {mx.x, mx.y, mx.z};
    return idx;
  }
  int vec2(const std::vector<glm::vec2>& v) {
    std::string b(v.size() * 8, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    return accessor(b, 5126, v.size(), "VEC2");
  }
  int u16(const std::vector<std::uint16_t>& v) {
    std::string b(v.size() * 2, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    return accessor(b, 5123, v.size(), "SCALAR");
  }
  int u32(const std::vector<std::uint32_t>& v) {
    std::string b(v.size() * 4, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    return accessor(b, 5125, v.size(), "SCALAR");
  }

  // .gltf with the buffer (and images) embedded as data URIs.
  std::string gltfText() const {
    json d = doc;
    d["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return d.dump(1);
  }
  std::string glb() const {
    json d = doc;
    d["buffers"] = {{{"byteLength", bin.size()}}};
    std::string js = d.dump();
    while (js.size() % 4) js += ' ';
    std::string b = bin;
    while (b.size() % 4) b += '\0';
    auto le32 = [](std::uint32_t v) { return std::string{char(v & 255), char((v >> 8) & 255), char((v >> 16) & 255), char(v >> 24)}; };
    const auto total = static_cast<std::uint32_t>(12 + 8 + js.size() + 8 + b.size());
    return "glTF" + le32(2) + le32(total) + le32(std::uint32_t(js.size())) + "JSON" + js + le32(std::uint32_t(b.size())) +
           std::string("BIN\0", 4) + b;
  }
};

const std::vector<std::uint8_t> kTexels = {255, 0, 0, 255, 0, 255, 0, 255,  // top row: red, green
                                           0, 0, 255, 255, 255, 255, 255, 128};  // bottom: blue, translucent white

// Hierarchy (scene 1, the default; scene 0 is a decoy holding only "hinge"):
//   root  T(10,0,0)
//   +- mid  R(90 deg about z) S(2,1,1)
//   |  +- leaf  matrix = T(0,0,5)            mesh 0: one triangle with normals, UVs, textured material
//   +- mirror  S(-1,1,1)                     mesh 1: one triangle, no normals, not indexed
//   hinge  T(0,0,-3)                         mesh 2: two triangles sharing an edge, no normals, no material,
//                                                    plus a POINTS primitive far away (must be skipped)
GltfBuilder testScene(bool image_in_buffer_view) {
  GltfBuilder g;
  const float r = 1.0f / std::sqrt(3.0f);
  json mesh0 = {{"primitives",
                 {{{"attributes",
                    {{"POSITION", g.vec3({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}})},
                     {"NORMAL", g.vec3({{r, r, r}, {r, r, r}, {r, r, r}})},
                     {"TEXCOORD_0", g.vec2({{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}})}}},
                   {"indices", g.u16({0, 1, 2})},
                   {"material", 0}}}}};
  json mesh1 = {{"primitives", {{{"attributes", {{"POSITION", g.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}}}, {"material", 1}}}}};
  json mesh2 = {{"primitives",
                 {{{"attributes", {{"POSITION", g.vec3({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 1}})}}},
                   {"indices", g.u32({0, 1, 2, 0, 2, 3})}},
                  {{"attributes", {{"POSITION", g.vec3({{100, 100, 100}})}}}, {"mode", 0}}}}};
  g.doc["meshes"] = {mesh0, mesh1, mesh2};
  const float h = std::sqrt(0.5f);
  g.doc["nodes"] = {
      {{"name", "root"}, {"translation", {10, 0, 0}}, {"children", {1, 3}}},
      {{"name", "mid"}, {"rotation", {0, 0, h, h}}, {"scale", {2, 1, 1}}, {"children", {2}}},
      {{"name", "leaf"}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}, {"mesh", 0}},
      {{"name", "mirror"}, {"scale", {-1, 1, 1}}, {"mesh", 1}},
      {{"name", "hinge"}, {"translation", {0, 0, -3}}, {"mesh", 2}},
  };
  g.doc["scenes"] = {{{"nodes", {4}}}, {{"nodes", {0, 4}}}};
  g.doc["scene"] = 1;
  g.doc["materials"] = {
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 0.75, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}},
      {{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.0, 0.0, 1.0}}}}},
  };
  g.doc["textures"] = {{{"source", 0}}};
  const std::string png = pngRgba(2, 2, kTexels);
  if (image_in_buffer_view)
    g.doc["images"] = {{{"bufferView", g.view(png)}, {"mimeType", "image/png"}}};
  else
    g.doc["images"] = {{{"uri", "data:image/png;base64," + base64(png)}}};
  return g;
}

using Tri = std::array<ml::Vertex, 3>;

std::vector<Tri> trianglesWithColor(const ml::Scene& s, glm::vec4 color, int* texture = nullptr) {
  std::vector<Tri> out;
  for (const auto& b : s.batches) {
    const ml::Material& m = s.materials.at(b.material);
    if (glm::length(m.base_color - color) > 1e-6f) continue;
    if (texture) *texture = m.base_color_texture;
    for (std::uint32_t i = b.first_index; i < b.first_index + b.index_count; i += 3)
      out.push_back({s.vertices.at(s.indices.at(i)), s.vertices.at(s.indices.at(i + 1)), s.vertices.at(s.indices.at(i + 2))});
  }
  return out;
}

::testing::AssertionResult near3(glm::vec3 got, glm::vec3 want, float tol = 1e-5f) {
  if (glm::length(got - want) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x
                                       << ", " << want.y << ", " << want.z << ")";
}

// The triangle's corners must be `want` in the same cyclic order (winding kept).
::testing::AssertionResult sameTriangle(const Tri& t, const std::array<glm::vec3, 3>& want) {
  for (int shift = 0; shift < 3; ++shift) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && glm::length(t[(k + shift) % 3].position - want[k]) < 1e-5f;
    if (ok) return ::testing::AssertionSuccess();
  }
  auto f = ::testing::AssertionFailure() << "triangle";
  for (const auto& v : t) f << " (" << v.position.x << ", " << v.position.y << ", " << v.position.z << ")";
  f << " is not";
  for (const auto& p : want) f << " (" << p.x << ", " << p.y << ", " << p.z << ")";
  return f;
}

glm::vec3 faceNormal(const Tri& t) {
  return glm::normalize(glm::cross(t[1].position - t[0].position, t[2].position - t[0].position));
}

void checkTestScene(const ml::Scene& s) {
  ASSERT_EQ(s.triangleCount(), 4u);  // the POINTS primitive contributes nothing

  // leaf: p -> T(10,0,0) R_z(90) S(2,1,1) T(0,0,5) p, worked out by hand:
  //   (1,0,0) -> (1,0,5) -> (2,0,5) -> (0,2,5) -> (10,2,5)
  //   (0,1,0) -> (0,1,5) -> (0,1,5) -> (-1,0,5) -> (9,0,5)
  //   (0,0,1) -> (0,0,6) -> (0,0,6) -> (0,0,6) -> (10,0,6)
  int texture = -2;
  const auto leaf = trianglesWithColor(s, {0.25f, 0.5f, 0.75f, 1.0f}, &texture);
  ASSERT_EQ(leaf.size(), 1u);
  EXPECT_TRUE(sameTriangle(leaf[0], {glm::vec3(10, 2, 5), glm::vec3(9, 0, 5), glm::vec3(10, 0, 6)}));
  // Normal (1,1,1): inverse transpose of S(2,1,1) gives (0.5,1,1), R_z(90) gives
  // (-1,0.5,1), normalised (-2,1,2)/3 -- perpendicular to the transformed
  // triangle, which a plain (non inverse-transpose) transform would not be.
  for (const auto& v : leaf[0]) EXPECT_TRUE(near3(v.normal, glm::vec3(-2, 1, 2) / 3.0f));
  EXPECT_TRUE(near3(faceNormal(leaf[0]), glm::vec3(-2, 1, 2) / 3.0f));
  for (const auto& v : leaf[0]) {
    // UVs follow their vertices: (10,2,5) came from (1,0,0) whose uv is (0,0), and so on.
    glm::vec2 want = glm::length(v.position - glm::vec3(10, 2, 5)) < 1e-4f   ? glm::vec2(0, 0)
                     : glm::length(v.position - glm::vec3(9, 0, 5)) < 1e-4f ? glm::vec2(1, 0)
                                                                             : glm::vec2(0, 1);
    EXPECT_EQ(v.uv, want);
  }
  ASSERT_GE(texture, 0);
  ASSERT_LT(static_cast<std::size_t>(texture), s.textures.size());
  const ml::Texture& tex = s.textures[static_cast<std::size_t>(texture)];
  EXPECT_EQ(tex.width, 2);
  EXPECT_EQ(tex.height, 2);
  EXPECT_EQ(tex.rgba8, kTexels);  // row 0 = top: red first

  // mirror: S(-1,1,1) then T(10,0,0); mirroring reverses the winding, so the
  // loader must swap it back: the stored triangle must face +z like the source.
  const auto mirror = trianglesWithColor(s, {1, 0, 0, 1});
  ASSERT_EQ(mirror.size(), 1u);
  EXPECT_TRUE(sameTriangle(mirror[0], {glm::vec3(10, 0, 0), glm::vec3(10, 1, 0), glm::vec3(9, 0, 0)}));
  EXPECT_TRUE(near3(faceNormal(mirror[0]), {0, 0, 1}));
  for (const auto& v : mirror[0]) {
    EXPECT_TRUE(near3(v.normal, {0, 0, 1}));
    EXPECT_EQ(v.uv, glm::vec2(0.0f));  // no TEXCOORD_0
  }

  // hinge (no material -> default white): generated normals are area weighted.
  // Triangle A B C has area 2 facing +z, A C D area 1 facing +x, so the shared
  // corners get (2*2*(0,0,1) + 2*1*(1,0,0)) normalised = (1,0,2)/sqrt(5).
  int hinge_texture = -2;
  const auto hinge = trianglesWithColor(s, {1, 1, 1, 1}, &hinge_texture);
  ASSERT_EQ(hinge.size(), 2u);
  EXPECT_EQ(hinge_texture, -1);
  const glm::vec3 A(0, 0, -3), B(2, 0, -3), C(0, 2, -3), D(0, 0, -2);
  const bool first_is_abc = glm::length(hinge[0][0].position - B) < 1e-5f || glm::length(hinge[0][1].position - B) < 1e-5f ||
                            glm::length(hinge[0][2].position - B) < 1e-5f;
  const Tri& abc = first_is_abc ? hinge[0] : hinge[1];
  const Tri& acd = first_is_abc ? hinge[1] : hinge[0];
  EXPECT_TRUE(sameTriangle(abc, {A, B, C}));
  EXPECT_TRUE(sameTriangle(acd, {A, C, D}));
  const glm::vec3 shared = glm::vec3(1, 0, 2) / std::sqrt(5.0f);
  for (const Tri* t : {&abc, &acd})
    for (const auto& v : *t) {
      const glm::vec3 want = glm::length(v.position - B) < 1e-5f   ? glm::vec3(0, 0, 1)
                             : glm::length(v.position - D) < 1e-5f ? glm::vec3(1, 0, 0)
                                                                   : shared;
      EXPECT_TRUE(near3(v.normal, want)) << "vertex at z=" << v.position.z;
    }

  EXPECT_TRUE(near3(s.bounds.min, {0, 0, -3}));
  EXPECT_TRUE(near3(s.bounds.max, {10, 2, 6}));  // the far-away point primitive is not in the bounds

  std::uint32_t covered = 0;
  for (const auto& b : s.batches) {
    EXPECT_EQ(b.first_index, covered);
    covered += b.index_count;
  }
  EXPECT_EQ(covered, s.indices.size());
}

TEST(SceneGltf, HierarchyTransformsNormalsAndTexture) {
  TempDir dir;
  const std::string path = dir.file("hierarchy.gltf");
  writeBytes(path, testScene(false).gltfText());
  const ml::Scene s = ml::loadGltfScene(path);
  EXPECT_EQ(s.source, path);
  checkTestScene(s);
}

TEST(SceneGltf, GlbWithImageInBufferView) {
  TempDir dir;
  const std::string path = dir.file("hierarchy.glb");
  writeBytes(path, testScene(true).glb());
  checkTestScene(ml::loadGltfScene(path));
}

TEST(SceneGltf, ExternalBufferFileNextToTheGltf) {
  TempDir dir;
  GltfBuilder g = testScene(false);
  json d = g.doc;
  d["buffers"] = {{{"byteLength", g.bin.size()}, {"uri", "payload.bin"}}};
  writeBytes(dir.file("payload.bin"), g.bin);
  writeBytes(dir.file("external.gltf"), d.dump());
  checkTestScene(ml::loadGltfScene(dir.file("external.gltf")));
}

TEST(SceneGltf, TriangleStripAndFanKeepTheirWinding) {
  TempDir dir;
  GltfBuilder g;
  // Both cover the unit square in z = 0, counter-clockwise seen from +z.
  const int strip = g.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  const int fan = g.vec3({{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", strip}}}, {"mode", 5}},
                                      {{"attributes", {{"POSITION", fan}}}, {"mode", 6}}}}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.doc["scenes"] = {{{"nodes", {0}}}};
  const std::string path = dir.file("strips.gltf");
  writeBytes(path, g.gltfText());
  const ml::Scene s = ml::loadGltfScene(path);
  ASSERT_EQ(s.triangleCount(), 4u);
  float area = 0.0f;
  for (std::size_t i = 0; i < s.indices.size(); i += 3) {
    const Tri t = {s.vertices[s.indices[i]], s.vertices[s.indices[i + 1]], s.vertices[s.indices[i + 2]]};
    const glm::vec3 c = glm::cross(t[1].position - t[0].position, t[2].position - t[0].position);
    EXPECT_GT(c.z, 0.0f) << "triangle " << i / 3 << " faces away";
    area += glm::length(c) / 2;
    for (const auto& v : t) EXPECT_TRUE(near3(v.normal, {0, 0, 1}));
  }
  EXPECT_NEAR(area, 2.0f, 1e-6f);  // two unit squares, no overlap or gap
}

TEST(SceneGltf, UndecodableTextureFallsBackToTheFactor) {
  TempDir dir;
  GltfBuilder g = testScene(true);
  g.doc["images"][0]["bufferView"] = g.view("this is not a PNG file at all");
  const std::string path = dir.file("badpng.glb");
  writeBytes(path, g.glb());
  const ml::Scene s = ml::loadGltfScene(path);
  EXPECT_EQ(s.triangleCount(), 4u);
  int texture = -2;
  EXPECT_EQ(trianglesWithColor(s, {0.25f, 0.5f, 0.75f, 1.0f}, &texture).size(), 1u);
  EXPECT_EQ(texture, -1);
}

// Expects a one-line UserError that names the file.
void expectUserError(const std::string& path, const std::string& also = "") {
  ml::test::expectFileError([&] { (void)ml::loadGltfScene(path); }, path, also);
}

TEST(SceneGltfErrors, MissingFile) {
  TempDir dir;
  expectUserError(dir.file("does-not-exist.glb"), "not found");
}

TEST(SceneGltfErrors, TruncatedGlb) {
  TempDir dir;
  const std::string glb = testScene(true).glb();
  for (std::size_t keep : {std::size_t(6), std::size_t(40), glb.size() / 2, glb.size() - 4}) {
    SCOPED_TRACE(keep);
    const std::string path = dir.file("truncated" + std::to_string(keep) + ".glb");
    writeBytes(path, glb.substr(0, keep));
    expectUserError(path);
  }
}

TEST(SceneGltfErrors, InvalidJson) {
  TempDir dir;
  const std::string path = dir.file("broken.gltf");
  writeBytes(path, "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [\n");
  expectUserError(path);
  const std::string empty = dir.file("empty.gltf");
  writeBytes(empty, "");
  expectUserError(empty);
}

TEST(SceneGltfErrors, AccessorPastItsBuffer) {
  TempDir dir;
  GltfBuilder g = testScene(false);
  g.doc["accessors"][0]["count"] = 1000;  // POSITION of mesh 0: 3 vec3 really stored
  const std::string path = dir.file("overrun.gltf");
  writeBytes(path, g.gltfText());
  expectUserError(path);

  GltfBuilder h = testScene(false);
  h.doc["accessors"][1]["byteOffset"] = 4096;
  const std::string offset_path = dir.file("offset.gltf");
  writeBytes(offset_path, h.gltfText());
  expectUserError(offset_path);
}

TEST(SceneGltfErrors, ImageBufferViewOutsideItsBuffer) {
  TempDir dir;
  GltfBuilder g = testScene(true);
  const int image_view = g.doc["images"][0]["bufferView"];
  g.doc["bufferViews"][image_view]["byteLength"] = 1 << 20;
  const std::string path = dir.file("image-overrun.glb");
  writeBytes(path, g.glb());
  expectUserError(path, "image 0");
}

TEST(SceneGltfErrors, IndexOutOfRange) {
  TempDir dir;
  GltfBuilder g = testScene(false);
  g.doc["meshes"][0]["primitives"][0]["indices"] = g.u16({0, 1, 7});
  const std::string path = dir.file("bad-index.gltf");
  writeBytes(path, g.gltfText());
  expectUserError(path, "out of range");
}

TEST(SceneGltfErrors, NoTriangles) {
  TempDir dir;
  GltfBuilder g;
  const int pos = g.vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"mode", 1}}}}}};  // LINES
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.doc["scenes"] = {{{"nodes", {0}}}};
  const std::string path = dir.file("lines.gltf");
  writeBytes(path, g.gltfText());
  expectUserError(path, "no triangles");

  const std::string empty_path = dir.file("nothing.gltf");
  writeBytes(empty_path, R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}]})");
  expectUserError(empty_path, "no triangles");
}

TEST(SceneGltfErrors, NodeCycle) {
  TempDir dir;
  GltfBuilder g = testScene(false);
  g.doc["nodes"][2]["children"] = {0};  // leaf -> root
  const std::string path = dir.file("cycle.gltf");
  writeBytes(path, g.gltfText());
  expectUserError(path, "ancestor");
}

TEST(SceneGltfErrors, DanglingReferences) {
  TempDir dir;
  GltfBuilder g = testScene(false);
  g.doc["nodes"][3]["mesh"] = 9;
  const std::string path = dir.file("dangling.gltf");
  writeBytes(path, g.gltfText());
  expectUserError(path);
}

// ---------------------------------------------------------------------------
// The shipped default scene

const std::string kDefault = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/default/";

TEST(SceneDefault, LoadsWithSaneContent) {
  const ml::Scene s = ml::loadGltfScene(kDefault + "scene.glb");
  EXPECT_GE(s.triangleCount(), 500u);
  EXPECT_LE(s.triangleCount(), 5000u);

  const glm::vec3 extent = s.bounds.max - s.bounds.min;
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(std::isfinite(s.bounds.min[a]) && std::isfinite(s.bounds.max[a]));
    EXPECT_GT(extent[a], 5.0f) << "axis " << a;
    EXPECT_LT(extent[a], 100.0f) << "axis " << a;
  }
  EXPECT_LT(extent.y, std::min(extent.x, extent.z)) << "a level of rooms is wider than it is tall";

  // Several visibly different materials, at least one with a decoded texture.
  std::vector<glm::vec4> colours;
  bool textured = false;
  for (const auto& b : s.batches) {
    const ml::Material& m = s.materials.at(b.material);
    bool seen = false;
    for (auto& c : colours) seen = seen || glm::length(c - m.base_color) < 1e-3f;
    if (!seen) colours.push_back(m.base_color);
    if (m.base_color_texture >= 0) {
      ASSERT_LT(static_cast<std::size_t>(m.base_color_texture), s.textures.size());
      const ml::Texture& t = s.textures[static_cast<std::size_t>(m.base_color_texture)];
      EXPECT_GT(t.width, 0);
      EXPECT_GT(t.height, 0);
      EXPECT_EQ(t.rgba8.size(), std::size_t(t.width) * t.height * 4);
      std::uint8_t lo = 255, hi = 0;
      for (std::size_t i = 0; i < t.rgba8.size(); i += 4) lo = std::min(lo, t.rgba8[i]), hi = std::max(hi, t.rgba8[i]);
      EXPECT_GT(hi - lo, 30) << "texture has a visible pattern";
      textured = true;
    }
  }
  EXPECT_GE(colours.size(), 4u);
  EXPECT_TRUE(textured);

  std::uint32_t covered = 0;
  for (const auto& b : s.batches) {
    EXPECT_EQ(b.first_index, covered);
    covered += b.index_count;
  }
  EXPECT_EQ(covered, s.indices.size());
  for (std::uint32_t i : s.indices) ASSERT_LT(i, s.vertices.size());

  // The scene has mirrored, rotated, uniformly and non-uniformly scaled
  // (sheared) instances; after loading, every triangle must still face where its
  // vertex normals point and the normals must be unit length.
  std::size_t checked = 0;
  for (std::size_t i = 0; i < s.indices.size(); i += 3) {
    const ml::Vertex& a = s.vertices[s.indices[i]];
    const ml::Vertex& b = s.vertices[s.indices[i + 1]];
    const ml::Vertex& c = s.vertices[s.indices[i + 2]];
    for (const ml::Vertex* v : {&a, &b, &c}) ASSERT_NEAR(glm::length(v->normal), 1.0f, 1e-3f);
    const glm::vec3 face = glm::cross(b.position - a.position, c.position - a.position);
    if (glm::length(face) < 1e-6f) continue;
    const glm::vec3 n = glm::normalize(face);
    for (const ml::Vertex* v : {&a, &b, &c})
      ASSERT_GT(glm::dot(n, v->normal), 0.9f) << "triangle " << i / 3 << " at (" << a.position.x << ", "
                                              << a.position.y << ", " << a.position.z << ")";
    ++checked;
  }
  EXPECT_GT(checked, s.triangleCount() * 9 / 10);
}

TEST(SceneDefault, CameraAndLightsLieInsideTheScene) {
  const ml::Scene s = ml::loadGltfScene(kDefault + "scene.glb");
  auto inside = [&](glm::vec3 p) {
    return glm::all(glm::greaterThan(p, s.bounds.min)) && glm::all(glm::lessThan(p, s.bounds.max));
  };
  const ml::CameraPath cams = ml::loadCameraJson(kDefault + "camera.json");
  for (std::size_t i = 0; i < cams.frames.size(); ++i) EXPECT_TRUE(inside(cams.frames[i].eye)) << "frame " << i;

  const auto lights = ml::loadLightsJson(kDefault + "lights.json");
  EXPECT_GE(lights.size(), 256u);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const auto& p = lights[i].position_radius;
    EXPECT_TRUE(inside({p.x, p.y, p.z})) << "light " << i;
    EXPECT_GE(p.w, 1.0f);
    EXPECT_LE(p.w, 5.0f);
  }

  // The default view looks into geometry: the scene's vertices in front of the
  // camera project inside the frustum in large numbers (not an empty view).
  const ml::Camera& cam = cams.frames.front();
  const glm::mat4 vp = cam.projection(16.0f / 9.0f) * cam.view();
  std::size_t visible = 0;
  for (const auto& v : s.vertices) {
    const glm::vec4 clip = vp * glm::vec4(v.position, 1.0f);
    if (clip.w > 0 && std::abs(clip.x) < clip.w && std::abs(clip.y) < clip.w && std::abs(clip.z) < clip.w) ++visible;
  }
  EXPECT_GT(visible, s.vertices.size() / 10);
}

}  // namespace
