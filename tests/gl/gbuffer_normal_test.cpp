// G-buffer normals: octahedral encoding into RG16 unorm (gl/shaders/
// octahedral.glsl). A C++ mirror of the GLSL states the angular error of the
// 16-bit round trip on many random normals and the octahedron's edge cases,
// and the GLSL itself (through a compute shader) is held to the mirror.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/shared/test_shader_bindings.h"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

glm::vec2 octSign(glm::vec2 v) { return {v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f}; }

glm::vec2 octEncode(glm::vec3 n) {
  glm::vec2 p = glm::vec2(n.x, n.y) / (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
  if (n.z < 0.0f) p = (1.0f - glm::abs(glm::vec2(p.y, p.x))) * octSign(p);
  return p * 0.5f + 0.5f;
}

glm::vec3 octDecode(glm::vec2 s) {
  const glm::vec2 e = s * 2.0f - 1.0f;
  glm::vec3 n(e, 1.0f - std::fabs(e.x) - std::fabs(e.y));
  const float t = std::max(-n.z, 0.0f);
  const glm::vec2 xy = glm::vec2(n.x, n.y) - t * octSign(glm::vec2(n.x, n.y));
  return glm::normalize(glm::vec3(xy, n.z));
}

// The RG16 unorm store (round to nearest, as packUnorm2x16 and the GL spec's
// recommended conversion).
std::uint32_t quantize(float v) { return std::uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f)); }

double angle(glm::vec3 a, glm::vec3 b) {
  const glm::dvec3 x = glm::normalize(glm::dvec3(a)), y = glm::normalize(glm::dvec3(b));
  return std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
}

std::vector<glm::vec3> testNormals(std::size_t random_count) {
  std::mt19937_64 rng(test::freshSeed());
  std::normal_distribution<float> g;
  std::vector<glm::vec3> n;
  for (int a = 0; a < 3; ++a)
    for (float s : {1.0f, -1.0f}) {
      glm::vec3 v(0.0f);
      v[a] = s;
      n.push_back(v);  // the octahedron's vertices
    }
  for (int k = 0; k < 360; ++k) {
    const float t = float(k) * 3.14159265f / 180.0f;
    n.push_back({std::cos(t), std::sin(t), 0.0f});           // the fold (z = 0)
    n.push_back({std::cos(t), std::sin(t), -1e-7f});         // just below it
    n.push_back(glm::normalize(glm::vec3(std::cos(t), 0.0f, std::sin(t))));  // y = 0 edges
  }
  while (n.size() < random_count) {
    const glm::vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) n.push_back(glm::normalize(v));
  }
  return n;
}

TEST(GBufferNormal, OctahedralRoundTripErrorOnRandomNormals) {
  const auto normals = testNormals(1000000);
  double max_err = 0.0, sum = 0.0;
  for (const auto& n : normals) {
    const glm::vec2 e = octEncode(n);
    ASSERT_TRUE(e.x >= 0.0f && e.x <= 1.0f && e.y >= 0.0f && e.y <= 1.0f) << n.x << " " << n.y << " " << n.z;
    const glm::vec3 d = octDecode(glm::vec2(float(quantize(e.x)) / 65535.0f, float(quantize(e.y)) / 65535.0f));
    const double a = angle(n, d);
    max_err = std::max(max_err, a);
    sum += a;
  }
  const double mean = sum / double(normals.size());
  std::printf("octahedral RG16 unorm round trip over %zu normals: max %.3g rad (%.4f deg), mean %.3g rad\n",
              normals.size(), max_err, max_err * 180.0 / 3.14159265358979, mean);
  // One 16-bit step over [-1, 1] is 3.05e-5; the octahedron stretches it by at most ~2.
  EXPECT_LT(max_err, 1e-4);
  EXPECT_LT(mean, 3e-5);
}

TEST(GBufferNormal, GlslEncodingMatchesTheMirror) {
  test::glContext();
  const auto normals = testNormals(65536);
  const auto n = std::uint32_t(normals.size());
  std::vector<glm::vec4> in;
  for (const auto& v : normals) in.emplace_back(v, 0.0f);
  GLuint bufs[3] = {0, 0, 0};
  glCreateBuffers(3, bufs);
  glNamedBufferStorage(bufs[0], n * 16, in.data(), 0);
  const std::vector<std::uint32_t> poison(std::size_t(n) * 4, 0xDEADBEEFu);
  glNamedBufferStorage(bufs[1], n * 4, poison.data(), 0);
  glNamedBufferStorage(bufs[2], n * 16, poison.data(), 0);
  ShaderProgram prog({"test/test_octahedral.comp"});
  prog.use();
  prog.set("u_n", n);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_OCTAHEDRAL_NORMALS, bufs[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_OCTAHEDRAL_PACKED, bufs[1]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_OCTAHEDRAL_DECODED, bufs[2]);
  glDispatchCompute((n + 63) / 64, 1, 1);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  std::vector<std::uint32_t> packed(n);
  std::vector<glm::vec4> decoded(n);
  glGetNamedBufferSubData(bufs[1], 0, n * 4, packed.data());
  glGetNamedBufferSubData(bufs[2], 0, n * 16, decoded.data());
  glDeleteBuffers(3, bufs);
  glCheck("octahedral compute test");
  double max_err = 0.0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::vec2 e = octEncode(normals[i]);
    const auto qx = std::int64_t(quantize(e.x)), qy = std::int64_t(quantize(e.y));
    const auto gx = std::int64_t(packed[i] & 0xffffu), gy = std::int64_t(packed[i] >> 16);
    // GLSL division and rounding may differ from C++ by an ulp: one step at most.
    ASSERT_LE(std::abs(gx - qx), 1) << "normal " << i;
    ASSERT_LE(std::abs(gy - qy), 1) << "normal " << i;
    max_err = std::max(max_err, angle(normals[i], glm::vec3(decoded[i])));
  }
  EXPECT_LT(max_err, 1e-4);
}

}  // namespace
}  // namespace ml
