#include "host/scene/LightSet.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

using scene_json::json;

// 53 random bits -> [0, 1). Spelled out (instead of std::uniform_real_distribution,
// whose algorithm is implementation-defined) so light sets are identical across
// standard libraries and scripts/make_default_scene.py can reproduce them.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

glm::dvec3 hueToRgb(double hue) {
  const double h6 = hue * 6.0;
  const double sector = std::floor(h6);
  const double f = h6 - sector;
  const double q = 1.0 - f;
  switch (static_cast<int>(sector) % 6) {
    case 0: return {1.0, f, 0.0};
    case 1: return {q, 1.0, 0.0};
    case 2: return {0.0, 1.0, f};
    case 3: return {0.0, q, 1.0};
    case 4: return {f, 0.0, 1.0};
    default: return {1.0, 0.0, q};
  }
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string gib(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return buf;
}

}  // namespace

std::uint64_t availableHostMemory() {
  std::uint64_t avail = std::numeric_limits<std::uint64_t>::max();
  std::ifstream meminfo("/proc/meminfo");
  std::string key, rest;
  std::uint64_t kib = 0;
  while (meminfo >> key >> kib) {
    std::getline(meminfo, rest);
    if (key == "MemAvailable:") {
      avail = kib * 1024;
      break;
    }
  }
  rlimit rl{};
  if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
    std::ifstream statm("/proc/self/statm");
    std::uint64_t pages = 0;
    statm >> pages;  // the address space in use now, in pages
    const std::uint64_t used = pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
    const std::uint64_t limit = static_cast<std::uint64_t>(rl.rlim_cur);
    avail = std::min(avail, limit > used ? limit - used : 0);
  }
  return avail;
}

void checkLightCount(const std::string& flag, std::uint64_t count, const std::string& what) {
  const std::string lights = std::to_string(count) + " lights" + (what.empty() ? "" : " (" + what + ")");
  if (count > kMaxLights)
    throw UserError(flag + ": " + lights + " exceed the maximum of " + std::to_string(kMaxLights) + " (2^27)");
  const std::uint64_t avail = availableHostMemory();
  const double need = static_cast<double>(count) * static_cast<double>(kHostBytesPerLight);
  if (need > static_cast<double>(avail))
    throw UserError(flag + ": " + lights + " need about " + gib(need) + " of memory (" +
                    std::to_string(kHostBytesPerLight) + " bytes each), only " + gib(static_cast<double>(avail)) +
                    " are available");
}

std::vector<gpu::PointLight> generateLights(const std::vector<LightVolume>& volumes, const LightGenParams& params) {
  if (!(params.radius > 0.0f) || !std::isfinite(params.radius))
    throw UserError("light generation: radius must be finite and > 0 (got " + std::to_string(params.radius) + ")");
  if (!(params.radius_jitter >= 0.0f && params.radius_jitter < 1.0f))
    throw UserError("light generation: radius jitter must be in [0, 1) (got " + std::to_string(params.radius_jitter) +
                    ")");
  double total = 0.0;
  for (std::size_t i = 0; i < volumes.size(); ++i) {
    const LightVolume& v = volumes[i];
    const std::string where = "light generation: volume " + std::to_string(i);
    if (!finite3(v.min) || !finite3(v.max)) throw UserError(where + ": bounds must be finite");
    if (v.min.x > v.max.x || v.min.y > v.max.y || v.min.z > v.max.z) throw UserError(where + ": min exceeds max");
    if (!(v.weight >= 0.0f) || !std::isfinite(v.weight)) throw UserError(where + ": weight must be finite and >= 0");
    total += v.weight;
  }
  std::vector<gpu::PointLight> lights;
  if (params.count == 0) return lights;
  if (!(total > 0.0)) throw UserError("light generation: no volume with a positive weight");

  std::size_t last_positive = 0;
  for (std::size_t i = 0; i < volumes.size(); ++i)
    if (volumes[i].weight > 0.0f) last_positive = i;

  std::mt19937_64 rng(params.seed);
  lights.reserve(params.count);
  for (std::uint32_t n = 0; n < params.count; ++n) {
    const double target = uniform01(rng) * total;
    std::size_t box = last_positive;
    double cumulative = 0.0;
    for (std::size_t i = 0; i < volumes.size(); ++i) {
      cumulative += volumes[i].weight;
      if (volumes[i].weight > 0.0f && target < cumulative) {
        box = i;
        break;
      }
    }
    const LightVolume& v = volumes[box];
    glm::vec3 p;
    for (int c = 0; c < 3; ++c) {
      const double lo = v.min[c], hi = v.max[c];
      p[c] = static_cast<float>(lo + uniform01(rng) * (hi - lo));
    }
    const glm::vec3 color(hueToRgb(uniform01(rng)));
    const double jitter = 1.0 + static_cast<double>(params.radius_jitter) * (2.0 * uniform01(rng) - 1.0);
    lights.push_back(makeLight(p, static_cast<float>(static_cast<double>(params.radius) * jitter), color));
  }
  return lights;
}

std::vector<gpu::PointLight> loadLightsJson(const std::string& path) {
  const json doc = scene_json::readFile(path, "light");
  if (!doc.is_object() || !doc.contains("lights"))
    throw UserError(path + ": light file needs a top-level object with a \"lights\" array");
  const json& list = doc["lights"];
  if (!list.is_array()) throw UserError(path + ": \"lights\" must be an array");

  std::vector<gpu::PointLight> lights;
  lights.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = path + ": light " + std::to_string(i);
    const json& l = list[i];
    if (!l.is_object()) throw UserError(where + ": must be an object");
    const glm::vec3 position = scene_json::toVec3(scene_json::member(l, "position", where), where, "position", "xyz");
    const glm::vec3 intensity =
        scene_json::toVec3(scene_json::member(l, "intensity", where), where, "intensity", "rgb");
    const float radius = scene_json::toFloat(scene_json::member(l, "radius", where), where, "radius");
    if (!(radius > 0.0f)) throw UserError(where + ": \"radius\" must be > 0 (got " + std::to_string(radius) + ")");
    if (intensity.r < 0.0f || intensity.g < 0.0f || intensity.b < 0.0f)
      throw UserError(where + ": \"intensity\" must not be negative");
    lights.push_back(makeLight(position, radius, intensity));
  }
  return lights;
}

void saveLightsJson(const std::string& path, const std::vector<gpu::PointLight>& lights) {
  // One light per line: diffable and about a third of the size of an indented dump.
  std::string text = "{\"lights\": [";
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const auto& pr = lights[i].position_radius;
    const auto& c = lights[i].color;
    nlohmann::ordered_json l;
    l["position"] = scene_json::storable(glm::vec3(pr.x, pr.y, pr.z));
    l["radius"] = scene_json::storable(pr.w);
    l["intensity"] = scene_json::storable(glm::vec3(c.x, c.y, c.z));
    text += (i ? ",\n  " : "\n  ") + l.dump();
  }
  text += lights.empty() ? "]}\n" : "\n]}\n";
  scene_json::writeFile(path, text, "light");
}

LightVolumeSet loadLightVolumesJson(const std::string& path) {
  const json doc = scene_json::readFile(path, "light volume");
  if (!doc.is_object()) throw UserError(path + ": light volume file needs a top-level object");
  auto vit = doc.find("volumes");
  if (vit == doc.end() || !vit->is_array() || vit->empty())
    throw UserError(path + ": \"volumes\" must be a non-empty array");

  LightVolumeSet set;
  double total = 0.0;
  for (std::size_t i = 0; i < vit->size(); ++i) {
    const std::string where = path + ": volume " + std::to_string(i);
    const json& v = (*vit)[i];
    if (!v.is_object()) throw UserError(where + ": must be an object");
    LightVolume vol;
    vol.min = scene_json::toVec3(scene_json::member(v, "min", where), where, "min");
    vol.max = scene_json::toVec3(scene_json::member(v, "max", where), where, "max");
    if (vol.min.x > vol.max.x || vol.min.y > vol.max.y || vol.min.z > vol.max.z)
      throw UserError(where + ": \"min\" exceeds \"max\"");
    if (auto w = v.find("weight"); w != v.end()) vol.weight = scene_json::toFloat(*w, where, "weight");
    if (vol.weight < 0.0f) throw UserError(where + ": \"weight\" must be >= 0");
    total += vol.weight;
    set.volumes.push_back(vol);
  }
  if (!(total > 0.0)) throw UserError(path + ": no volume has a positive weight");

  LightGenParams& d = set.defaults;
  if (auto r = doc.find("radius"); r != doc.end()) {
    d.radius = scene_json::toFloat(*r, path, "radius");
    if (!(d.radius > 0.0f)) throw UserError(path + ": \"radius\" must be > 0");
  }
  if (auto j = doc.find("radius_jitter"); j != doc.end()) {
    d.radius_jitter = scene_json::toFloat(*j, path, "radius_jitter");
    if (!(d.radius_jitter >= 0.0f && d.radius_jitter < 1.0f))
      throw UserError(path + ": \"radius_jitter\" must be in [0, 1)");
  }
  if (auto s = doc.find("surface_inset"); s != doc.end()) {
    set.surface_inset = scene_json::toFloat(*s, path, "surface_inset");
    if (!(set.surface_inset >= 0.0f)) throw UserError(path + ": \"surface_inset\" must be >= 0");
  }
  if (auto s = doc.find("seed"); s != doc.end()) {
    if (!s->is_number_unsigned()) throw UserError(path + ": \"seed\" must be a non-negative integer");
    d.seed = s->get<std::uint64_t>();
  }
  if (auto c = doc.find("count"); c != doc.end()) {
    if (!c->is_number_unsigned() || c->get<std::uint64_t>() > 0xffffffffull)
      throw UserError(path + ": \"count\" must be a non-negative 32-bit integer");
    d.count = static_cast<std::uint32_t>(c->get<std::uint64_t>());
  }
  return set;
}

std::vector<gpu::PointLight> generateLightsIn(const std::string& volumes_path, glm::vec3 lo, glm::vec3 hi,
                                              std::uint32_t count, std::uint64_t seed, float radius,
                                              float density) {
  LightVolumeSet vf;
  if (!volumes_path.empty()) {
    vf = loadLightVolumesJson(volumes_path);
  } else {
    vf.volumes = {LightVolume{lo, hi, 1.0f}};
  }
  LightGenParams gp = vf.defaults;
  gp.count = count;
  gp.seed = seed;
  const glm::vec3 ext = hi - lo;
  if (radius > 0 && density > 0)
    throw UserError("light generation: give a radius or a density, not both");
  if (radius > 0) gp.radius = radius;
  else if (density > 0) {
    for (LightVolume& v : vf.volumes) {  // out to the surfaces (LightVolumeSet::surface_inset)
      v.min -= glm::vec3(vf.surface_inset);
      v.max += glm::vec3(vf.surface_inset);
    }
    gp.radius = densityRadius(vf.volumes, count, density, gp.radius_jitter);
  }
  else if (volumes_path.empty()) gp.radius = std::max({ext.x, ext.y, ext.z}) / 20.0f;
  return generateLights(vf.volumes, gp);
}

std::string densityLabel(float density, const std::vector<gpu::PointLight>& lights) {
  if (!(density > 0.0f)) return "";
  double sum = 0.0;
  for (const gpu::PointLight& l : lights) sum += l.position_radius.w;
  char buf[96];
  std::snprintf(buf, sizeof buf, " at density %g (mean r %.4g)", static_cast<double>(density),
                lights.empty() ? 0.0 : sum / static_cast<double>(lights.size()));
  return buf;
}

void checkLightDensityFlag(float density, float radius, bool generated) {
  if (density == 0.0f) return;
  if (!(density > 0.0f) || !std::isfinite(density))
    throw UserError("--light-density: must be finite and > 0 (got " + std::to_string(density) + ")");
  if (radius != 0.0f) throw UserError("--light-density: give --light-radius or --light-density, not both");
  if (!generated)
    throw UserError("--light-density: only generated lights (--lights N) take a density; light files carry their radii");
}

float densityRadius(const std::vector<LightVolume>& volumes, std::uint64_t count, float density, float jitter) {
  if (!(density > 0.0f) || !std::isfinite(density))
    throw UserError("light generation: density must be finite and > 0 (got " + std::to_string(density) + ")");
  double volume = 0.0;
  for (const LightVolume& v : volumes)
    if (v.weight > 0.0f) {
      const glm::dvec3 e = glm::dvec3(v.max) - glm::dvec3(v.min);
      volume += e.x * e.y * e.z;
    }
  if (count == 0 || !(volume > 0.0) || !std::isfinite(volume))
    throw UserError("light generation: a density needs at least one light and volumes that enclose space");
  const double j = static_cast<double>(jitter);
  const double pi = 3.14159265358979323846;
  const double r3 = 3.0 * static_cast<double>(density) * volume /
                    (4.0 * pi * kSurfaceCoverage * static_cast<double>(count) * (1.0 + j * j));
  return static_cast<float>(std::cbrt(r3));
}

}  // namespace ml
