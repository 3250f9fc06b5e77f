#include "host/assign/Techniques.hpp"

#include "host/assign/BruteForceAssigner.hpp"
#include "host/cl/KernelLimits.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "host/util/Error.hpp"

namespace ml {

const std::vector<TechniqueInfo>& techniques() {
  static const std::vector<TechniqueInfo> list = {
      {"forward", Pipeline::Forward, "brute-force forward shading: every light for every fragment"},
      {"deferred", Pipeline::Deferred, "brute-force deferred shading: G-buffer, then every light per pixel"},
      {"hashed-forward", Pipeline::Forward, "hashed shading, forward: camera-independent linkless octree of perfect spatial hashes", hashed::kMaxHashedLights},
      {"hashed-deferred", Pipeline::Deferred, "hashed shading, deferred: camera-independent linkless octree of perfect spatial hashes", hashed::kMaxHashedLights},
      {"tiled-forward", Pipeline::Forward, "forward+: depth pre-pass, per-tile light culling (OpenCL), forward shading"},
      {"tiled-deferred", Pipeline::Deferred, "tiled deferred: per-tile light culling (OpenCL) over the G-buffer depth"},
      {"clustered-forward", Pipeline::Forward, "clustered forward: depth pre-pass, cluster keys, unique clusters and light BVH (OpenCL)"},
      {"clustered-deferred", Pipeline::Deferred, "clustered deferred: cluster keys, unique clusters and light BVH (OpenCL) over the G-buffer depth"},
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
  if (t.name == "hashed-forward" || t.name == "hashed-deferred") return std::make_unique<HashedAssigner>(t.name, params);
  if (t.name == "tiled-forward" || t.name == "tiled-deferred")
    return std::make_unique<TiledAssigner>(cl, params.tile_size, parseTileDepthMode(params.tile_depth),
                                           parseKernelShape(params.kernel_shape));
  if (t.name == "clustered-forward" || t.name == "clustered-deferred")
    return std::make_unique<ClusteredAssigner>(cl, params.cluster_tile, parseUniqueMethod(params.unique_method),
                                               parseClusterAssign(params.cluster_assign),
                                               parseClusterBounds(params.cluster_bounds),
                                               parseKernelShape(params.kernel_shape));
  throw UserError("--technique: '" + technique + "' is registered but has no assigner");
}

}  // namespace ml
