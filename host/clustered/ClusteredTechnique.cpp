// The clustered technique's descriptor: names, parameters, the cluster view, factory.
#include "host/cl/KernelLimits.hpp"
#include "host/clustered/ClusteredAssigner.hpp"

namespace ml {

const TechniqueDescriptor& clusteredTechnique() {
  static const TechniqueDescriptor d = [] {
    TechniqueDescriptor t;
    t.family = "clustered";
    t.names = {
        {"clustered-forward", Pipeline::Forward,
         "clustered forward: depth pre-pass, cluster keys, unique clusters and light BVH (OpenCL)"},
        {"clustered-deferred", Pipeline::Deferred,
         "clustered deferred: cluster keys, unique clusters and light BVH (OpenCL) over the G-buffer depth"},
    };
    t.params = {
        countParam("cluster_tile", "auto", 1, kMaxClusterTile, "cluster tile size in pixels; auto: 32 from 720 "
                   "lines up (the thesis's), 16 below, down to 8 as the lights get small on screen", {"auto", "0"}),
        choiceParam("unique", "pagetable", {"pagetable", "sort", "tile-sort"}, "unique-cluster method"),
        choiceParam("cluster_assign", "bvh", {"bvh", "brute"}, "cluster light assignment"),
        choiceParam("cluster_bounds", "pixels", {"pixels", "frustum"},
                    "cull against the AABB of each cluster's pixels or of its sub-frustum"),
        kernelShapeParam(),
    };
    t.debug_views = {{"cluster", "write each unique cluster as a colour to this image (.png/.exr)"}};
    t.make = [](const TechniqueContext& c) -> std::unique_ptr<LightAssigner> {
      return std::make_unique<ClusteredAssigner>(
          c.cl, c.params.count("cluster_tile"), parseUniqueMethod(c.params.text("unique")),
          parseClusterAssign(c.params.text("cluster_assign")), parseClusterBounds(c.params.text("cluster_bounds")),
          parseKernelShape(c.params.text("kernel_shape")));
    };
    return t;
  }();
  return d;
}

std::vector<float> ClusteredAssigner::debugViewRgba(const std::string& view, const DebugViewInputs&) {
  return view == "cluster" ? clusterViewRgba(readClusterMap()) : std::vector<float>{};
}

}  // namespace ml
