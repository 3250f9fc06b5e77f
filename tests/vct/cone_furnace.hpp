#pragma once
// What the furnace tests of the cone tracing share (vct_furnace_test.cpp, one
// grid; vct_cascade_furnace_test.cpp, a camera-centred cascade): random
// points and normals inside a world box, traceDiffuse at them through
// gl/shaders/test/test_vct_cones.comp, and the error of the result against a
// uniform radiance L. Header-only: the test binary globs *_test.cpp.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/shared/vct_bindings.h"
#include "host/shared/voxel_types.h"
#include "host/vct/ConeTracing.hpp"

namespace ml::vct::furnace {

using F4 = gpu::ml_float4;

inline GLuint upload(const std::vector<F4>& v) {
  GLuint b = 0;
  glCreateBuffers(1, &b);
  glNamedBufferData(b, static_cast<GLsizeiptr>(std::max<std::size_t>(v.size(), 1) * sizeof(F4)), v.data(),
                    GL_STATIC_DRAW);
  glCheck("uploading a test buffer");
  return b;
}

// traceDiffuse at each point (world space) with its normal; `program` is
// test/test_vct_cones.comp built with coneTracingDefines() for s's levels.
inline std::vector<F4> trace(const ShaderProgram& program, const ConeTraceSetup& s, const std::vector<F4>& points,
                             const std::vector<F4>& normals) {
  program.use();
  bindConeTracing(program, s);
  const GLuint p = upload(points), n = upload(normals);
  std::vector<F4> out(points.size(), F4{-1, -1, -1, -1});
  const GLuint o = upload(out);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_CONES_POINTS, p);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_CONES_NORMALS, n);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_CONES_RESULTS, o);
  program.set("u_count", static_cast<unsigned>(points.size()));
  glDispatchCompute(static_cast<GLuint>((points.size() + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(o, 0, static_cast<GLsizeiptr>(out.size() * sizeof(F4)), out.data());
  const GLuint all[] = {p, n, o};
  glDeleteBuffers(3, all);
  glCheck("tracing test cones");
  return out;
}

// Per point, the largest relative error of the irradiance / pi against L over the channels.
inline std::vector<float> pointErrors(const std::vector<F4>& r, const F4& L) {
  std::vector<float> e;
  e.reserve(r.size());
  for (const F4& v : r)
    e.push_back(std::max({std::fabs(v.x - L.x) / L.x, std::fabs(v.y - L.y) / L.y, std::fabs(v.z - L.z) / L.z}));
  return e;
}

// Largest relative error of the irradiance / pi against L, and largest ambient occlusion.
inline std::pair<float, float> worst(const std::vector<F4>& r, const F4& L) {
  const std::vector<float> e = pointErrors(r, L);
  float ao = 0;
  for (const F4& v : r) ao = std::max(ao, std::fabs(v.w));
  return {e.empty() ? 0.0f : *std::max_element(e.begin(), e.end()), ao};
}

// `count` random points uniform in [lo, hi]^3 (world) and random unit normals.
inline void randomPoints(std::mt19937_64& rng, float lo, float hi, std::vector<F4>& points, std::vector<F4>& normals,
                         int count) {
  std::uniform_real_distribution<float> in(lo, hi);
  std::normal_distribution<float> g;
  for (int i = 0; i < count; ++i) {
    points.push_back({in(rng), in(rng), in(rng), 1});
    const float x = g(rng), y = g(rng), z = g(rng);
    const float len = std::sqrt(x * x + y * y + z * z) + 1e-20f;
    normals.push_back({x / len, y / len, z / len, 0});
  }
}

}  // namespace ml::vct::furnace
