#pragma once
// Helpers shared by the scene JSON readers/writers (lights, light volumes,
// cameras). Internal to host/scene; every failure is a one-line UserError that
// starts with the file path.
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "host/util/Error.hpp"

namespace ml::scene_json {

using nlohmann::json;

inline std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

inline json readFile(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(path + ": cannot open " + what + " file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw UserError(path + ": cannot read " + what + " file");
  try {
    return json::parse(buffer.str());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers like 1e999
    throw UserError(path + ": invalid JSON in " + what + " file: " + oneLine(e.what()));
  }
}

inline void writeFile(const std::string& path, const std::string& text, const char* what) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw UserError(path + ": cannot write " + what + " file");
  out << text;
  out.close();
  if (!out) throw UserError(path + ": error while writing " + what + " file");
}

// Floats are stored as the double of their shortest decimal form, so files stay
// readable ("0.1" rather than "0.10000000149011612") while loading (text ->
// double -> float) still gives back the identical float.
inline double storable(float f) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf - 1, f);
  if (ec == std::errc()) {
    *end = '\0';
    const double d = std::strtod(buf, nullptr);
    if (static_cast<float>(d) == f) return d;
  }
  return static_cast<double>(f);
}

inline json storable(const glm::vec3& v) { return json::array({storable(v.x), storable(v.y), storable(v.z)}); }

inline std::string describe(const json& v) {
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// `where` is "<path>: <element>" and prefixes every message.
inline float toFloat(const json& v, const std::string& where, const char* field) {
  if (!v.is_number()) throw UserError(where + ": \"" + field + "\" must be a number (got " + describe(v) + ")");
  const float f = static_cast<float>(v.get<double>());
  if (!std::isfinite(f)) throw UserError(where + ": \"" + field + "\" must be finite (got " + describe(v) + ")");
  return f;
}

inline const json& member(const json& obj, const char* key, const std::string& where) {
  auto it = obj.find(key);
  if (it == obj.end()) throw UserError(where + ": missing \"" + key + "\"");
  return *it;
}

// Accepts [a, b, c] or an object with the three given keys ({"x":..} / {"r":..}),
// the latter being how the nTiled suite writes vectors and colours.
inline glm::vec3 toVec3(const json& v, const std::string& where, const char* field, const char* keys = "xyz") {
  glm::vec3 out;
  if (v.is_array()) {
    if (v.size() != 3)
      throw UserError(where + ": \"" + field + "\" must have 3 elements (got " + std::to_string(v.size()) + ")");
    for (int i = 0; i < 3; ++i) out[i] = toFloat(v[i], where, field);
    return out;
  }
  if (v.is_object()) {
    for (int i = 0; i < 3; ++i) {
      const std::string key(1, keys[i]);
      auto it = v.find(key);
      if (it == v.end()) throw UserError(where + ": \"" + field + "\" has no \"" + key + "\"");
      out[i] = toFloat(*it, where, field);
    }
    return out;
  }
  throw UserError(where + ": \"" + field + "\" must be a 3-element array (got " + describe(v) + ")");
}

}  // namespace ml::scene_json
