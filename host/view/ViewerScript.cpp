#include "host/view/ViewerScript.hpp"

#include <fstream>
#include <map>
#include <sstream>

#include "host/gi/Registry.hpp"
#include "host/util/Error.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {
namespace {

using nlohmann::json;

enum class Shape { String, Count, Number, Bool, Object, Pair, Triple };

// The GI passes' view parameters are verbs too (their keys, e.g. voxel_level):
// a count is a JSON number, anything else a string.
void addGiViewVerbs(std::map<std::string, Shape>& v) {
  for (const GiDescriptor* d : giDescriptors())
    for (const ParamSpec& p : d->view_params) v.emplace(p.key, p.type == ParamType::Count ? Shape::Count : Shape::String);
}

bool isGiViewVerb(const std::string& verb) { return giViewParamOwner(verb) != nullptr; }

// Every verb and the shape of its value.
const std::map<std::string, Shape>& verbs() {
  static const std::map<std::string, Shape> v = [] {
    std::map<std::string, Shape> m = {
      {"technique", Shape::String},   {"param", Shape::Object},      {"lights", Shape::Count},
      {"animate", Shape::Pair},       {"view", Shape::String},       {"heatmap_max", Shape::Count},
      {"camera_frame", Shape::Count}, {"orbit", Shape::Pair},        {"fly", Shape::Triple},
      {"wait", Shape::Count},         {"screenshot", Shape::String}, {"screenshot_window", Shape::String},
      {"panel", Shape::Bool},         {"counts", Shape::Bool},       {"record", Shape::String},
      {"record_save", Shape::String}, {"ratio_max", Shape::Number},  {"play", Shape::Bool},
      {"gi", Shape::String},          {"gi_param", Shape::Object}};
    addGiViewVerbs(m);
    return m;
  }();
  return v;
}

bool numbers(const json& v, std::size_t n) {
  if (!v.is_array() || v.size() != n) return false;
  for (const auto& x : v)
    if (!x.is_number()) return false;
  return true;
}

bool fits(Shape s, const json& v) {
  switch (s) {
    case Shape::String: return v.is_string() && !v.get<std::string>().empty();
    case Shape::Count: return v.is_number_unsigned();
    case Shape::Number: return v.is_number();
    case Shape::Bool: return v.is_boolean();
    case Shape::Object: return v.is_object() && !v.empty();
    case Shape::Pair: return numbers(v, 2);
    case Shape::Triple: return numbers(v, 3);
  }
  return false;
}

const char* expected(Shape s) {
  switch (s) {
    case Shape::String: return "a non-empty string";
    case Shape::Count: return "a non-negative integer";
    case Shape::Number: return "a number";
    case Shape::Bool: return "true or false";
    case Shape::Object: return "an object of KEY: \"VALUE\"";
    case Shape::Pair: return "[number, number]";
    case Shape::Triple: return "[number, number, number]";
  }
  return "";
}

json readScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError("--script: cannot open " + path);
  std::stringstream text;
  text << in.rdbuf();
  try {
    return json::parse(text.str());
  } catch (const json::exception& e) {
    std::string what = e.what();
    for (char& c : what)
      if (c == '\n') c = ' ';
    throw UserError("--script: " + path + ": invalid JSON: " + what);
  }
}

float num(const json& v, std::size_t i) { return static_cast<float>(v.at(i).get<double>()); }

}  // namespace

ViewerScript ViewerScript::load(const std::string& path) {
  json doc = readScript(path);
  if (doc.is_object() && doc.contains("actions")) doc = doc["actions"];
  if (!doc.is_array()) throw UserError("--script: " + path + ": expected an array of actions (or {\"actions\": [...]})");
  ViewerScript script;
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const std::string where = "--script: " + path + ": action " + std::to_string(i);
    if (!doc[i].is_object() || doc[i].size() != 1) throw UserError(where + ": expected an object with one key");
    // The key and value through an iterator of doc[i] itself: items() returns a
    // temporary proxy that its element would outlive (ASan: stack-use-after-scope).
    const auto entry = doc[i].begin();
    const std::string verb = entry.key();
    const json& value = entry.value();
    const auto shape = verbs().find(verb);
    if (shape == verbs().end()) throw UserError(where + ": unknown action '" + verb + "'");
    if (!fits(shape->second, value))
      throw UserError(where + " (" + verb + "): expected " + expected(shape->second) + ", got " + value.dump());
    if (shape->second == Shape::Object)
      for (const auto& [k, v] : value.items())
        if (!v.is_string()) throw UserError(where + " (" + verb + "): \"" + k + "\" must be a string");
    if (verb == "record" && value != "start") throw UserError(where + " (record): expected \"start\"");
    script.actions_.push_back({verb, value, where + " (" + verb + ")"});
  }
  return script;
}

bool ViewerScript::step(ViewerSession& session, ScriptWindowActions& window) {
  if (waiting_ > 0) {
    --waiting_;
    return true;
  }
  while (next_ < actions_.size()) {
    const ScriptAction& a = actions_[next_++];
    if (a.verb == "wait") {
      waiting_ = a.value.get<unsigned>();
      if (waiting_ > 0) {
        --waiting_;
        return true;
      }
      continue;
    }
    run(a, session, window);
  }
  return false;
}

void ViewerScript::run(const ScriptAction& a, ViewerSession& s, ScriptWindowActions& window) {
  try {
    const json& v = a.value;
    if (a.verb == "technique") s.setTechnique(v.get<std::string>());
    else if (a.verb == "param")
      for (const auto& [k, x] : v.items()) s.setParam(k, x.get<std::string>());
    else if (a.verb == "lights") s.setLightCount(v.get<std::uint64_t>());
    else if (a.verb == "animate") s.setAnimation(num(v, 0), num(v, 1));
    else if (a.verb == "view") s.setViewMode(v.get<std::string>());
    else if (a.verb == "heatmap_max") s.setHeatmapMax(v.get<std::uint32_t>());
    else if (a.verb == "ratio_max") s.setRatioMax(v.get<double>());
    else if (a.verb == "play") s.setPlaying(v.get<bool>());
    else if (a.verb == "camera_frame") s.setCameraFrame(v.get<std::size_t>());
    else if (a.verb == "orbit") s.camera().orbit(num(v, 0), num(v, 1));
    else if (a.verb == "fly") s.camera().fly(num(v, 0), num(v, 1), num(v, 2));
    else if (a.verb == "screenshot") s.screenshot(v.get<std::string>());
    else if (a.verb == "screenshot_window") window.window_screenshot = v.get<std::string>();
    else if (a.verb == "panel") window.panel = v.get<bool>();
    else if (a.verb == "counts") {
      if (v.get<bool>()) s.requestCounts();
    } else if (a.verb == "record") s.startRecording();
    else if (a.verb == "record_save") s.saveRecording(v.get<std::string>());
    else if (a.verb == "gi") s.setGi(v.get<std::string>());
    else if (a.verb == "gi_param")
      for (const auto& [k, x] : v.items()) s.setGiParam(k, x.get<std::string>());
    else if (isGiViewVerb(a.verb)) s.setGiView(a.verb, v.is_string() ? v.get<std::string>() : v.dump());
  } catch (const UserError& e) {
    throw UserError(a.where + ": " + e.what());
  }
}

}  // namespace ml
