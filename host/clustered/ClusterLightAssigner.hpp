#pragma once
// Lights -> unique clusters on the device (kernels/clustered/: cluster_bounds.cl,
// light_bvh.cl, cluster_assign.cl, one program each):
//
//   ClusterLightAssigner a(rt, ClusterAssignMethod::Bvh);
//   a.boxes(q, cam, grid, unique_keys, clusters, timer, &pixels);  // explicit bounds (null: sub-frustum)
//   uint32_t records = a.assign(q, lights, n, cam);   // blocks for the total
//   ... make `records` hold >= records uint2s, `leaf_lights` >= leafLightSlots() uints ...
//   a.fill(q, ranges, records, leaf_lights);   // ranges: LightRange per cluster, in records
// (count() = boxes() + assign().)
//
// A cluster's list is a run of hit records (slot, mask): bit b of mask set
// means light leaf_lights[slot + b] reaches the cluster box. A record stands
// for all the hits of one leaf (11 lights on average at 100k lights, 720p), so
// the lists are several times smaller than index lists, and the device never
// expands them: the shader walks the masks (gl/shaders/clustered/lookup_clustered.glsl).
//
// Lights are packed leafSize() to a leaf (structure of arrays) and tested a
// leaf at a time into a hit mask. Brute: every cluster tests every leaf of the
// lights in their given order (the reference). Bvh: the lights that reach
// the box around all cluster boxes (the leaf test on it, so no list changes;
// compacted on the device, the count read back), Morton codes of their
// view-space centres (quantized in their bounding cube, reduced on the
// device), radix sort, leaves of the sorted lights and a BVH of branching 32
// over them (boxes and bounding spheres), rebuilt from scratch each assign()
// (bottom-up, one launch per level); each cluster walks it, the clusters
// taken in tile-Morton order so that consecutive walks share leaves. Both
// use the same leaf test, so their lists are the same sets
// (BVH lists in Morton order, brute force ascending). Lists are count -> scan
// -> fill and never truncate: count() records each cluster's hit leaves
// in a bounded scratch, fill() copies them into place and walks again only
// for clusters whose hits did not fit. Not thread-safe.
//
// Kernel shape (--kernel-shape): CpuChunked runs a work-item per tile, chunk,
// leaf, node or cluster (PoCL runs each as a plain loop); GpuWorkGroup runs a
// work-group per tile, chunk, leaf, node or cluster (32 work-items walking the
// BVH together through local memory). Both build the same boxes, tree and
// records in the same order; Auto picks by device type.
#include <CL/opencl.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelLimits.hpp"
#include "host/clustered/ClusterGeometry.hpp"
#include "host/compute/Compact.hpp"
#include "host/compute/RadixSort.hpp"
#include "host/compute/Scan.hpp"

namespace ml {

enum class ClusterAssignMethod { Bvh, Brute };
ClusterAssignMethod parseClusterAssign(const std::string& s);  // "bvh" | "brute"; UserError
const char* clusterAssignName(ClusterAssignMethod m);

// The box each cluster is culled against: Pixels, the view-space AABB of the
// pixels that fall in it (explicit bounds, from the depth buffer and the
// pixel -> cluster map); Frustum, the AABB of its whole sub-frustum (implicit
// bounds, from the key alone).
enum class ClusterBounds { Pixels, Frustum };
ClusterBounds parseClusterBounds(const std::string& s);  // "pixels" | "frustum"; UserError
const char* clusterBoundsName(ClusterBounds b);

// Inputs of the explicit bounds: window depth and the map from unique().
struct ClusterPixels {
  const cl::Buffer& depth;
  const cl::Buffer& cluster_of;
};

class ClusterLightAssigner {
 public:
  // leaf_size: lights per leaf, 8, 16 or 32 (UserError otherwise). Smaller
  // leaves test fewer lights that miss but make the walk longer; on PoCL 32 is
  // the fastest (bench/RESULTS-clustered.md), and it is a warp on a GPU.
  // max_group: most work-items per group of every kernel, the compute
  // primitives' included (0: what the device allows each kernel; tests force
  // 32 .. the device maximum); at least 32, the BVH walk's group (UserError).
  ClusterLightAssigner(ClRuntime& rt, ClusterAssignMethod method, unsigned leaf_size = 32,
                       KernelShape shape = KernelShape::Auto, std::size_t max_group = 0);

  // boxes() then assign(). pixels: explicit bounds from these pixels; null: sub-frustum bounds.
  std::uint32_t count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
                      const ClusterGrid& g, const cl::Buffer& unique_keys, std::uint32_t clusters,
                      ClPassTimer* timer = nullptr, const ClusterPixels* pixels = nullptr);
  // The clusters' boxes, once per frame whatever the assignment method.
  void boxes(cl::CommandQueue& q, const gpu::CameraParams& cam, const ClusterGrid& g, const cl::Buffer& unique_keys,
             std::uint32_t clusters, ClPassTimer* timer = nullptr, const ClusterPixels* pixels = nullptr);
  // Lights -> the clusters of the last boxes(); returns the records in all lists (blocks).
  std::uint32_t assign(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
                       ClPassTimer* timer = nullptr);
  // Same frame as the preceding assign(): `clusters` LightRanges (offset and
  // count in records), the records (uint2: first leaf slot, hit mask) and the
  // light index of every leaf slot (0xffffffff past the last light).
  void fill(cl::CommandQueue& q, cl::Buffer& ranges, cl::Buffer& records, cl::Buffer& leaf_lights,
            ClPassTimer* timer = nullptr);
  // Leaf slots of the last assign() (lights rounded up to whole leaves).
  std::size_t leafLightSlots() const { return std::size_t(n_leaves_) * leaf_size_; }

  ClusterAssignMethod method() const { return method_; }
  void setMethod(ClusterAssignMethod m) { method_ = m; }
  unsigned bvhLevels() const { return levels_; }
  // Bvh: the lights of the last assign() that reach the clusters' union box
  // (the BVH's lights); brute force: all of them.
  std::uint32_t treeLights() const { return tree_lights_; }
  unsigned leafSize() const { return leaf_size_; }
  KernelShape shape() const { return shape_; }  // resolved, never Auto
  // The last count()'s boxes (lo, hi as x, y, z(distance), 0), for tests.
  const cl::Buffer& boxLo() const { return box_lo_; }
  const cl::Buffer& boxHi() const { return box_hi_; }
  std::size_t scratchBytes() const;
  // Summed over the last assign()'s clusters (blocking; for reports and
  // tests): records (leaves with at least one hit), and lights in the lists.
  std::uint64_t hitLeaves(cl::CommandQueue& q) const { return sumOver(q, hit_leaves_); }
  std::uint64_t listedLights(cl::CommandQueue& q) const { return sumOver(q, counts_); }
  // Hit-leaf records (8 bytes each) shared by all clusters (default 2^22);
  // clusters with more hit leaves than their share are walked again by fill().
  void setRecordBudget(std::size_t records) { record_budget_ = records; }
  // Bvh: walk the clusters in tile-Morton order (default; sorted in assign())
  // or in key order. The lists are the same; brute force always uses key order.
  void setClusterOrder(bool morton) { cluster_order_ = morton; }

 private:
  void fitLocalSizes();
  void launchShaped(cl::CommandQueue& q, const cl::Kernel& k, std::size_t elements, std::size_t group,
                    cl::Event* event) const;
  void packLeaves(cl::CommandQueue& q, const cl::Buffer& spheres, std::uint32_t n, bool bvh, ClPassTimer* timer);
  std::uint32_t keepReachingLights(cl::CommandQueue& q, std::uint32_t n, ClPassTimer* timer);
  void buildBvh(cl::CommandQueue& q, std::uint32_t n, ClPassTimer* timer);
  template <typename... Rest>
  void setAssignArgs(cl::Kernel& k, const Rest&... rest);
  void orderClusters(cl::CommandQueue& q, std::uint32_t clusters, ClPassTimer* timer);
  std::uint64_t sumOver(cl::CommandQueue& q, const cl::Buffer& per_cluster) const;

  ClRuntime& rt_;
  ClusterAssignMethod method_;
  unsigned leaf_size_;
  KernelShape shape_;
  bool gpu_ = false;
  cl::Program bounds_program_, bvh_program_, lists_program_;  // the three parts of the pass
  cl::Kernel view_, boxes_, pixel_boxes_, morton_, pack_, level_, blocks_, count_k_, fill_k_, ranges_;
  cl::Kernel bounds_part_, bounds_final_, order_k_, finish_;
  cl::Kernel union_part_, union_final_, reaches_k_, gather_k_, remap_k_;
  // Work-group sizes: per-element kernels, and the GPU shape's groups (per
  // tile, reduction, leaf, node, cluster), fitted to each kernel's limits.
  std::size_t max_group_ = 0;
  std::size_t local_ = 1, pixel_local_ = 1, red_local_ = 1, leaf_local_ = 1, node_local_ = 1, walk_local_ = 1;
  cl::Buffer order_codes_, order_ids_, order_keys_;
  ClusterGrid order_grid_;
  std::size_t order_capacity_ = 0;
  bool cluster_order_ = true, use_order_ = false;
  cl::Buffer part_lo_, part_hi_, frame_, box_union_;
  cl::Buffer reaching_, reaching_spheres_;  // BVH: the lights that reach a cluster, and their spheres
  cl::Buffer spheres_, codes_, ids_, soa_, leaf_ids_, node_lo_, node_hi_, node_sph_, node_soa_, block_start_;
  cl::Buffer box_lo_, box_hi_, counts_, offsets_, bounds_, rec_leaf_, rec_mask_, hit_leaves_;
  std::size_t light_capacity_ = 0, leaf_capacity_ = 0, node_capacity_ = 0, cluster_capacity_ = 0;
  std::size_t bounds_capacity_ = 0, record_capacity_ = 0, block_capacity_ = 0, part_capacity_ = 0;
  std::uint32_t n_ = 0, clusters_ = 0, n_leaves_ = 0, slots_ = 0, tree_lights_ = 0;
  unsigned levels_ = 0;
  bool bvh_ = false;
  std::size_t record_budget_;
  compute::Scanner scan_;
  compute::RadixSorter radix_;
  compute::Compactor compact_;
};

}  // namespace ml
