#include "host/vct/VctSettingsTable.hpp"

#include <cmath>
#include <cstdio>

#include "host/util/Error.hpp"

namespace ml::vct {
namespace {

unsigned parseCount(const std::string& key, const std::string& t) {
  std::size_t used = 0;
  unsigned long v = 0;
  try {
    if (t.empty() || t[0] == '-' || t[0] == '+') throw std::invalid_argument(t);
    v = std::stoul(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != t.size() || v > 0xFFFFFFFFul)
    throw UserError("--" + key + ": expected a non-negative integer, got '" + t + "'");
  return static_cast<unsigned>(v);
}

float parseNumber(const std::string& key, const std::string& t) {
  std::size_t used = 0;
  float v = 0;
  try {
    v = std::stof(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != t.size() || !std::isfinite(v))
    throw UserError("--" + key + ": expected a number, got '" + t + "'");
  return v;
}

bool parseSwitch(const std::string& key, const std::string& t) {
  if (t == "on" || t == "true" || t == "1") return true;
  if (t == "off" || t == "false" || t == "0") return false;
  throw UserError("--" + key + ": expected on|off, got '" + t + "'");
}

std::string number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", double(v));
  return buf;
}

std::string onOff(bool v) { return v ? "on" : "off"; }

}  // namespace

const std::vector<VctSetting>& vctSettings() {
  using T = VctSettingType;
  using S = VctGiSettings;
  using K = const std::string&;
  static const std::vector<VctSetting> table = {
      {"voxels", "level-0 voxels per axis (a power of two up to 512)", T::Count, {},
       [](const S& s) { return std::to_string(s.grid.voxels); },
       [](S& s, K k, K t) { s.grid.voxels = parseCount(k, t); }},
      {"levels", "mip levels (1..log2(voxels) + 1)", T::Count, {},
       [](const S& s) { return std::to_string(s.grid.levels); },
       [](S& s, K k, K t) { s.grid.levels = parseCount(k, t); }},
      {"anisotropic", "anisotropic voxels (6 directions per voxel)", T::Switch, {},
       [](const S& s) { return onOff(s.grid.anisotropic); },
       [](S& s, K k, K t) { s.grid.anisotropic = parseSwitch(k, t); }},
      {"cones", "diffuse cones per pixel (1..32)", T::Count, {}, [](const S& s) { return std::to_string(s.cones); },
       [](S& s, K k, K t) { s.cones = parseCount(k, t); }},
      {"cone-aperture", "diffuse cone aperture in degrees (0..180)", T::Number, {},
       [](const S& s) { return number(s.aperture_deg); }, [](S& s, K k, K t) { s.aperture_deg = parseNumber(k, t); }},
      {"gi-scale", "trace resolution as a fraction of the frame's, (0, 1]", T::Number, {},
       [](const S& s) { return number(s.gi_scale); }, [](S& s, K k, K t) { s.gi_scale = parseNumber(k, t); }},
      {"specular", "add a specular cone (reflectance 0.04, aperture 10 degrees)", T::Switch, {},
       [](const S& s) { return onOff(s.specular); }, [](S& s, K k, K t) { s.specular = parseSwitch(k, t); }},
      {"vct-shadows", "visibility of the lights in the injected direct light (none, or voxel: marched through level-0 opacity)",
       T::Choice, {"none", "voxel"}, [](const S& s) { return s.shadows; },
       [](S& s, K, K t) { s.shadows = t; }},
      {"revoxelize", "voxelize the scene every frame (moving geometry), not only the first", T::Switch, {},
       [](const S& s) { return onOff(s.revoxelize); }, [](S& s, K k, K t) { s.revoxelize = parseSwitch(k, t); }},
  };
  return table;
}

void parseVctSetting(VctGiSettings& s, const std::string& key, const std::string& text) {
  std::string keys;
  for (const VctSetting& v : vctSettings()) {
    if (v.key == key) return v.set(s, key, text);
    keys += (keys.empty() ? "" : "|") + v.key;
  }
  throw UserError("gi_param: unknown VCT setting '" + key + "' (" + keys + ")");
}

VctGiSettings withVctSetting(VctGiSettings s, const std::string& key, const std::string& text) {
  parseVctSetting(s, key, text);
  checkVctGiSettings(s);
  return s;
}

}  // namespace ml::vct
