#pragma once
// What a technique and the GL renderer agree on without either including the
// other's folder: the pipeline a technique runs in, and the defines its GLSL
// lookup is compiled with. gl/ includes this header; host/assign includes
// nothing from gl/ (tests/arch/arch_include_graph_test.cpp keeps the folders acyclic).
//   forward : [depth pre-pass -> depth export] -> assign (CL) -> forward shading
//   deferred: G-buffer -> [depth export] -> assign (CL) -> full-screen shading
#include <string>
#include <utility>
#include <vector>

namespace ml {

enum class Pipeline { Forward, Deferred };
inline const char* pipelineName(Pipeline p) { return p == Pipeline::Forward ? "forward" : "deferred"; }

// GLSL #defines (name, value) a technique adds to the shading programs.
using ShaderDefines = std::vector<std::pair<std::string, std::string>>;

}  // namespace ml
