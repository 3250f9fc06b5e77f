#pragma once
// The technique registry: `--technique NAME` maps to a pipeline (forward or
// deferred) and a LightAssigner factory. New techniques add themselves here
// and nowhere else; the frame loop never knows which one runs.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/assign/LightAssigner.hpp"

namespace ml {

// Technique parameters from the command line; each technique reads what it needs.
struct TechniqueParams {
  // Tiled shading (--tile, --tile-depth-bounds)
  unsigned tile_size = 16;
  std::string tile_depth = "minmax";  // none | minmax | mask (2.5D)
  // Clustered shading (--cluster-tile, --unique, --cluster-assign, --cluster-bounds)
  unsigned cluster_tile = 0;  // 0: auto, the thesis's 32 px from 720 lines up, 16 px below
  std::string unique_method = "pagetable";  // pagetable | sort | tile-sort
  std::string cluster_assign = "bvh";       // bvh | brute
  std::string cluster_bounds = "pixels";    // pixels (explicit, AABB of the cluster's pixels) | frustum (implicit)
  // Hashed shading (--node-size, --start-depth, --geometry-mask, --no-octant-masks)
  std::string node_size = "0.5r";  // absolute world units ("2.0") or relative to the median light radius ("0.5r")
  unsigned start_depth = 3;
  bool geometry_mask = false;
  bool octant_masks = true;
  // Kernel shape of the OpenCL passes (--kernel-shape): auto (by device type),
  // cpu (a work-item per element with private state) or gpu (work-groups
  // cooperating through local memory). Tiled and clustered shading and the
  // primitives they call; brute force and hashed shading have no CL passes.
  std::string kernel_shape = "auto";
};

struct TechniqueInfo {
  std::string name;         // "forward", "deferred", "tiled-forward", ...
  Pipeline pipeline;
  std::string description;  // one line for --help
  // The most lights the technique addresses (hashed: 24-bit list entries);
  // commands check --lights against it before generating or loading lights.
  std::uint32_t max_lights = UINT32_MAX;
};

const std::vector<TechniqueInfo>& techniques();
// Throws UserError listing the valid names when `name` is unknown.
const TechniqueInfo& findTechnique(const std::string& name);
std::unique_ptr<LightAssigner> makeAssigner(const std::string& technique, ClRuntime& cl, const TechniqueParams& params);
std::string techniqueNames();  // "forward|deferred|..."

}  // namespace ml
