#pragma once
// Cluster grid and the cluster math shared with kernels/clustered/cluster_keys.cl and
// kernels/clustered/cluster_bounds.cl, written once for the host so the tests can hold
// the kernels to it exactly (both sides compile without FP contraction).
//
// Key layout (32 bits, low to high): slice k (kBits), tile column i (xBits),
// tile row j (yBits); 0xffffffff marks sky. Tiles above slices make ascending
// keys tile-major, so a per-tile sort already yields the global order.
// Slices are exponential (main thesis ch. 6): slice k covers view distances
// [near * q^k, near * q^(k+1)), q = 1 + 2 tan(fovy/2) / tilesY, the last one
// reaching to far; the boundaries are computed here in double and handed to
// the kernels, which only compare against them.
#include <cstdint>
#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

constexpr std::uint32_t kClusterInvalid = 0xffffffffu;
// Relative widening of the slice depth range and of the explicit (pixel)
// bounds in the cluster boxes: the shader reconstructs depth along another
// float path than the kernels, or interpolates its position (reversed-Z float
// depth fixes the distance to ~1e-7 relative at any near plane).
constexpr float kClusterDepthEps = 1e-4f;
// Largest cluster tile edge ClusterGrid::make takes; the clustered
// descriptor's `cluster_tile` range reads it.
constexpr unsigned kMaxClusterTile = 1024;

struct ClusterGrid {
  unsigned tile_size = 32;
  unsigned width = 0, height = 0;
  unsigned tiles_x = 0, tiles_y = 0, slices = 0;
  unsigned x_bits = 0, y_bits = 0, k_bits = 0;
  std::vector<float> slice_bounds;  // slices + 1 view distances, [0] = near, [slices] >= far

  // Throws UserError if the key does not fit in 31 bits (the sort needs one
  // spare bit above the key to put sky last).
  static ClusterGrid make(const gpu::CameraParams& cam, unsigned tile_size);
  unsigned keyBits() const { return x_bits + y_bits + k_bits; }
  std::uint32_t key(unsigned i, unsigned j, unsigned k) const { return (((j << x_bits) | i) << k_bits) | k; }
  unsigned sliceOf(std::uint32_t key) const { return key & ((1u << k_bits) - 1u); }
  unsigned tileX(std::uint32_t key) const { return (key >> k_bits) & ((1u << x_bits) - 1u); }
  unsigned tileY(std::uint32_t key) const { return key >> (k_bits + x_bits); }
  // Tile-major pixel order used by the per-tile sort: tiles_x * tiles_y + 1 offsets.
  std::vector<std::uint32_t> tileOffsets() const;
};

unsigned bitsFor(unsigned count);  // bits to hold 0 .. count - 1
// The automatic cluster tile (--cluster-tile auto): at most the thesis's 32 px
// from 720 lines up, 16 px below (where 32 px tiles are a tenth of the
// screen), and smaller as the lights get small on screen: the largest power of
// two, down to 8, at most kClusterTilePerLightPixel times coveringLightPixels()
// (host/assign/LightFootprint.hpp). On the default scene at constant density
// the lists' evaluations / exact bound follow tile / light pixels: 1.2 at
// 0.07, 1.45 at 0.125, 2.0 at 0.26, 3.6 at 0.51 (docs/scaling.md); 0.14 keeps
// them at 1.46 or below from 1k to 1M lights. light_pixels 0 (no light in
// view): the resolution's tile.
constexpr double kClusterTilePerLightPixel = 0.14;
unsigned autoClusterTile(unsigned width, unsigned height, double light_pixels = 0.0);
unsigned sliceOfDepth(float z, const ClusterGrid& g);
// depth: window-space floats, row 0 at the bottom.
std::vector<std::uint32_t> referenceKeys(const float* depth, const gpu::CameraParams& cam, const ClusterGrid& g);

// View-space AABB of a cluster's sub-frustum (z as positive distance).
struct ClusterBox {
  float x0, x1, y0, y1, z0, z1;
};
ClusterBox clusterBox(std::uint32_t key, const gpu::CameraParams& cam, const ClusterGrid& g);
// Explicit bounds: per unique cluster the view-space AABB of the centres of
// the pixels mapped to it (cluster_of: pixel -> cluster index or
// kClusterInvalid), widened relative to its extent (see kClusterDepthEps). Mirrors
// cluster_pixel_boxes in kernels/clustered/cluster_bounds.cl exactly.
std::vector<ClusterBox> pixelBoxes(const float* depth, const std::vector<std::uint32_t>& cluster_of,
                                   std::uint32_t clusters, const gpu::CameraParams& cam);
// View-space sphere (z negative in front of the camera).
struct ViewSphere {
  float x, y, z, r;
};
ViewSphere viewSphere(const gpu::PointLight& l, const gpu::CameraParams& cam);
bool sphereHitsCluster(const ViewSphere& s, const ClusterBox& b);
// Per unique cluster, ascending indices of the lights whose sphere reaches its box.
std::vector<std::vector<std::uint32_t>> referenceAssign(const std::vector<ClusterBox>& boxes,
                                                        const std::vector<gpu::PointLight>& lights,
                                                        const gpu::CameraParams& cam);
// The same over the clusters' sub-frustum boxes (implicit bounds).
std::vector<std::vector<std::uint32_t>> referenceAssign(const std::vector<std::uint32_t>& unique_keys,
                                                        const std::vector<gpu::PointLight>& lights,
                                                        const gpu::CameraParams& cam, const ClusterGrid& g);

}  // namespace ml
