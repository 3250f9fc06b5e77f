#pragma once
// The test-only GI pass (TestOnlyGiPass.cpp): `--gi test-ambient --ambient
// R:G:B` adds albedo x (R, G, B) to every covered pixel.
//  - parseAmbient(): "0.25:0.5:0.75" -> the colour; false unless three
//    finite non-negative numbers joined by ':' (',' would split bench lists).
#include <glm/glm.hpp>

#include <string>

namespace ml::test {

inline constexpr const char* kAmbientGiName = "test-ambient";
bool parseAmbient(const std::string& text, glm::vec3& colour);
std::string ambientProblem(const std::string& text);  // "" when accepted

}  // namespace ml::test
