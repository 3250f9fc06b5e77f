#include "host/suite/ThesisReference.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>

#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

using scene_json::json;

std::string fileNameOf(const std::string& p) {
  const auto cut = p.find_last_of("/\\");
  return cut == std::string::npos ? p : p.substr(cut + 1);
}

void readConfig(ReferenceSeries& s) {
  const json doc = scene_json::readFile(s.config_path, "reference config");
  if (!doc.is_object()) throw UserError(s.config_path + ": needs a top-level object");
  if (auto vp = doc.find("viewport"); vp != doc.end() && vp->is_object()) {
    if (vp->contains("width") && (*vp)["width"].is_number_unsigned()) s.width = (*vp)["width"].get<unsigned>();
    if (vp->contains("height") && (*vp)["height"].is_number_unsigned()) s.height = (*vp)["height"].get<unsigned>();
  }
  if (auto l = doc.find("lights"); l != doc.end() && l->is_array() && !l->empty() && (*l)[0].is_object() &&
                                    (*l)[0].contains("path") && (*l)[0]["path"].is_string())
    s.light_file = fileNameOf((*l)[0]["path"].get<std::string>());
  if (auto c = doc.find("camera"); c != doc.end() && c->is_object()) {
    if (c->contains("fovy") && (*c)["fovy"].is_number()) s.fovy = (*c)["fovy"].get<float>();
    if (auto clip = c->find("clip"); clip != c->end() && clip->is_object()) {
      if (clip->contains("near") && (*clip)["near"].is_number()) s.near_plane = (*clip)["near"].get<float>();
      if (clip->contains("far") && (*clip)["far"].is_number()) s.far_plane = (*clip)["far"].get<float>();
    }
  }
}

bool parseTile(const std::string& s, unsigned& out) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && ec == std::errc() && p == s.data() + s.size() && out > 0;
}

}  // namespace

std::map<std::size_t, double> readLcData(const std::string& path) {
  const json doc = scene_json::readFile(path, "light-calculation");
  if (!doc.is_object() || !doc.contains("frames") || !doc["frames"].is_array())
    throw UserError(path + ": expected {\"frames\": [{\"frame\": N, \"n_calc\": C}, ...]}");
  std::map<std::size_t, double> out;
  for (std::size_t i = 0; i < doc["frames"].size(); ++i) {
    const json& f = doc["frames"][i];
    const std::string where = path + ": frames[" + std::to_string(i) + "]";
    if (!f.is_object() || !f.contains("frame") || !f["frame"].is_number_unsigned() || !f.contains("n_calc") ||
        !f["n_calc"].is_number() || f["n_calc"].get<double>() < 0)
      throw UserError(where + ": needs \"frame\" (index) and \"n_calc\" (count >= 0)");
    out[f["frame"].get<std::size_t>()] = f["n_calc"].get<double>();
  }
  if (out.empty()) throw UserError(path + ": no frames");
  return out;
}

namespace {

// The folder holding frames/{ns,ts,cs}: `dir` is the suite root, reference/,
// reference/light_calculations/ or that folder itself.
std::string findFramesDir(const std::string& dir) {
  const fs::path base(dir);
  for (const fs::path& cand : {base / "frames", base / "light_calculations" / "frames",
                               base / "reference" / "light_calculations" / "frames", base})
    if (fs::is_directory(cand / "ns") || fs::is_directory(cand / "ts") || fs::is_directory(cand / "cs"))
      return cand.string();
  throw UserError("--reference: no frames/{ns,ts,cs} folders under '" + dir +
                  "' (expected the thesis-suite root, reference/ or reference/light_calculations/)");
}

// The reference's scene: `scene` as asked, or the only one present.
std::string chooseScene(const std::string& frames_dir, const std::string& scene, const std::string& pipeline) {
  const fs::path frames(frames_dir);
  if (!scene.empty() && fs::is_directory(frames / "ns" / pipeline / scene)) return scene;
  std::vector<std::string> found;
  std::error_code ec;
  for (const char* kind : {"ns", "ts", "cs"})
    for (const auto& e : fs::directory_iterator(frames / kind / pipeline, ec))
      if (e.is_directory() && std::find(found.begin(), found.end(), e.path().filename().string()) == found.end())
        found.push_back(e.path().filename().string());
  if (!scene.empty() && std::find(found.begin(), found.end(), scene) != found.end()) return scene;
  if (scene.empty() && found.size() == 1) return found.front();
  std::string list;
  for (const auto& f : found) list += (list.empty() ? "" : ", ") + f;
  throw UserError("--reference: " + frames_dir + " has no " + pipeline + " data for scene '" + scene +
                  "' (found: " + (list.empty() ? "none" : list) + ")");
}

// One series (`kind`, `tile` 0 for naive) from `folder`; a note instead when
// it has no lc_data.json, and a note for a missing config.json.
void addSeries(ThesisReference& ref, const std::string& kind, unsigned tile, const fs::path& folder) {
  ReferenceSeries s;
  s.kind = kind;
  s.tile = tile;
  s.id = tile ? kind + "/" + std::to_string(tile) : kind;
  s.lc_path = (folder / "lc_data.json").string();
  s.config_path = (folder / "config.json").string();
  if (!fs::is_regular_file(s.lc_path)) {
    ref.notes.push_back(s.id + ": no lc_data.json in " + folder.string() + " (skipped)");
    return;
  }
  if (fs::is_regular_file(s.config_path)) readConfig(s);
  else ref.notes.push_back(s.id + ": no config.json; assuming 320x320 and the suite's camera settings");
  s.counts = readLcData(s.lc_path);
  ref.series.push_back(std::move(s));
}

// Every tile-size folder of a tiled or clustered `kind`, in increasing size.
void addTiledSeries(ThesisReference& ref, const std::string& kind, const fs::path& folder) {
  std::vector<unsigned> tiles;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    unsigned t = 0;
    if (e.is_directory() && parseTile(e.path().filename().string(), t)) tiles.push_back(t);
  }
  std::sort(tiles.begin(), tiles.end());
  for (unsigned t : tiles) addSeries(ref, kind, t, folder / std::to_string(t));
}

}  // namespace

ThesisReference loadThesisReference(const std::string& dir, const std::string& scene, const std::string& pipeline) {
  ThesisReference ref;
  ref.pipeline = pipeline;
  ref.frames_dir = findFramesDir(dir);
  ref.scene = chooseScene(ref.frames_dir, scene, pipeline);
  const fs::path frames(ref.frames_dir);
  const fs::path ns = frames / "ns" / pipeline / ref.scene;
  if (fs::is_directory(ns)) addSeries(ref, "ns", 0, ns);
  for (const char* kind : {"ts", "cs"}) addTiledSeries(ref, kind, frames / kind / pipeline / ref.scene);
  if (ref.series.empty())
    throw UserError("--reference: no lc_data.json files under " + ref.frames_dir + " for scene '" + ref.scene + "'");
  return ref;
}

}  // namespace ml
