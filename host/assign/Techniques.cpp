#include "host/assign/Techniques.hpp"

#include "host/assign/BruteForceAssigner.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "host/util/Error.hpp"

namespace ml {

const std::vector<TechniqueInfo>& techniques() {
  static const std::vector<TechniqueInfo> list = {
      {"forward", Pipeline::Forward, "brute-force forward shading: every light for every fragment"},
      {"deferred", Pipeline::Deferred, "brute-force deferred shading: G-buffer, then every light per pixel"},
      {"tiled-forward", Pipeline::Forward, "forward+: depth pre-pass, per-tile light culling (OpenCL), forward shading"},
      {"tiled-deferred", Pipeline::Deferred, "tiled deferred: per-tile light culling (OpenCL) over the G-buffer depth"},
  };
  return list;
}

std::string techniqueNames() {
  std::string s;
  for (const auto& t : techniques()) s += (s.empty() ? "" : "|") + t.name;
  return s;
}

const TechniqueInfo& findTechnique(const std::string& name) {
  for (const auto& t : techniques())
    if (t.name == name) return t;
  throw UserError("--technique: unknown technique '" + name + "' (choose " + techniqueNames() + ")");
}

std::unique_ptr<LightAssigner> makeAssigner(const std::string& technique, ClRuntime& cl,
                                            const TechniqueParams& params) {
  const TechniqueInfo& t = findTechnique(technique);
  if (t.name == "forward" || t.name == "deferred") return std::make_unique<BruteForceAssigner>();
  if (t.name == "tiled-forward" || t.name == "tiled-deferred")
    return std::make_unique<TiledAssigner>(cl, params.tile_size, parseTileDepthMode(params.tile_depth));
  throw UserError("--technique: '" + technique + "' is registered but has no assigner");
}

}  // namespace ml
