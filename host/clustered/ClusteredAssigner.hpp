#pragma once
// Clustered shading as a LightAssigner (clustered forward with a depth
// pre-pass, clustered deferred over the G-buffer depth). Per frame, all on the
// CL device: cluster keys from the depth, unique clusters (ClusterUniquer, the
// --unique method) with the pixel -> cluster map written straight into a
// shared buffer, per-cluster light lists (ClusterLightAssigner, --cluster-assign)
// into shared buffers. Clusters are culled against the AABB of their pixels
// (explicit bounds, the default) or of their sub-frustum (--cluster-bounds).
// lookup_clustered.glsl reads the fragment's cluster from the map, then its
// (offset, count) range of hit records and walks their masks.
// SSBOs: 1 hit records (uvec2: leaf slot, mask), 2 cluster ranges (LightRange
// per unique cluster, in records), 3 pixel -> cluster map (uint per pixel,
// 0xffffffff = sky), 4 light index per leaf slot.
// clusteredTechnique(): the descriptor the registry lists, with the "cluster"
// debug view (ClusteredTechnique.cpp).
#include <memory>

#include "gl/SharedBuffer.hpp"
#include "host/assign/LightAssigner.hpp"
#include "host/assign/TechniqueDescriptor.hpp"
#include "host/clustered/ClusterLightAssigner.hpp"
#include "host/clustered/ClusterUniquer.hpp"

namespace ml {

class ClusteredAssigner final : public LightAssigner {
 public:
  // tile_size 0: autoClusterTile() of each frame's viewport and lights.
  ClusteredAssigner(ClRuntime& rt, unsigned tile_size, UniqueMethod unique, ClusterAssignMethod assign,
                    ClusterBounds bounds = ClusterBounds::Pixels, KernelShape shape = KernelShape::Auto);
  bool needsDepth() const override { return true; }
  void assign(const FrameInputs& in) override;
  std::string lookupShader() const override { return "clustered/lookup_clustered.glsl"; }
  void bindForShading(const ShaderProgram& program) const override;
  std::size_t memoryBytes() const override;
  std::vector<std::pair<std::string, double>> stats() const override;
  // "cluster": clusterViewRgba of the cluster map (the frame's depth is not needed).
  std::vector<float> debugViewRgba(const std::string& view, const DebugViewInputs& frame) override;

  // Last frame's outputs, for views and tests (host copies, blocking).
  std::vector<std::uint32_t> readClusterMap();
  std::uint32_t uniqueClusters() const { return clusters_; }
  // The cluster view: each unique cluster a colour (mixed from its index,
  // distinct for up to 2^18 clusters in an 8-bit image), sky black; RGBA
  // floats, row 0 bottom, for writeImage.
  static std::vector<float> clusterViewRgba(const std::vector<std::uint32_t>& cluster_map);
  const ClusterGrid& grid() const { return grid_; }

 private:
  ClRuntime& rt_;
  unsigned tile_size_;
  ClusterBounds bounds_;
  ClusterUniquer uniquer_;
  ClusterLightAssigner lights_;
  ClusterGrid grid_;
  std::unique_ptr<SharedBuffer> ranges_, records_, leaf_lights_, map_;
  std::uint32_t clusters_ = 0, last_records_ = 0;
  double light_pixels_ = 0.0;  // coveringLightPixels() of the last frame (auto tile only)
};

const TechniqueDescriptor& clusteredTechnique();

}  // namespace ml
