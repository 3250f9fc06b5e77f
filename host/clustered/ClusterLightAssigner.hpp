#pragma once
// Lights -> unique clusters on the device (kernels/cluster_assign.cl):
//
//   ClusterLightAssigner a(rt, ClusterAssignMethod::Bvh);
//   uint32_t total = a.count(q, lights, n, cam, grid, unique_keys, clusters);  // blocks for the total
//   ... make `indices` hold >= total uints ...
//   a.fill(q, ranges, indices);   // ranges: LightRange per cluster
//
// Brute: every cluster tests every light (the reference). Bvh: Morton codes of
// the view-space light centres (quantized in the view frustum's box; lights
// outside it clamp to its faces, which costs tree quality only), radix sort, a BVH of branching 32 rebuilt from
// scratch each count() (bottom-up, one launch per level), each cluster walks
// it. Both use the same sphere-vs-cluster-AABB test, so their lists are the
// same sets (the BVH lists are in Morton order, brute force ascending).
// Lists are count -> scan -> fill and never truncate. Not thread-safe.
#include <CL/opencl.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/clustered/ClusterGeometry.hpp"
#include "host/compute/RadixSort.hpp"
#include "host/compute/Scan.hpp"

namespace ml {

enum class ClusterAssignMethod { Bvh, Brute };
ClusterAssignMethod parseClusterAssign(const std::string& s);  // "bvh" | "brute"; UserError
const char* clusterAssignName(ClusterAssignMethod m);

class ClusterLightAssigner {
 public:
  ClusterLightAssigner(ClRuntime& rt, ClusterAssignMethod method);

  std::uint32_t count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n, const gpu::CameraParams& cam,
                      const ClusterGrid& g, const cl::Buffer& unique_keys, std::uint32_t clusters,
                      ClPassTimer* timer = nullptr);
  // Same frame as the preceding count(); writes `clusters` LightRanges.
  void fill(cl::CommandQueue& q, cl::Buffer& ranges, cl::Buffer& indices, ClPassTimer* timer = nullptr);

  ClusterAssignMethod method() const { return method_; }
  void setMethod(ClusterAssignMethod m) { method_ = m; }
  unsigned bvhLevels() const { return levels_; }
  std::size_t scratchBytes() const;

 private:
  void buildBvh(cl::CommandQueue& q, std::uint32_t n, ClPassTimer* timer);
  void runAssign(cl::CommandQueue& q, bool fill, cl::Buffer* indices, ClPassTimer* timer);

  ClRuntime& rt_;
  ClusterAssignMethod method_;
  cl::Program program_, keys_program_;
  cl::Kernel view_, boxes_, brute_, morton_, leaves_, level_, bvh_, ranges_;
  cl::Buffer spheres_, codes_, ids_, sorted_, sorted_ids_, node_lo_, node_hi_, level_start_, level_count_;
  cl::Buffer box_lo_, box_hi_, counts_, offsets_, bounds_;
  std::size_t light_capacity_ = 0, node_capacity_ = 0, cluster_capacity_ = 0, bounds_capacity_ = 0;
  std::uint32_t n_ = 0, clusters_ = 0;
  unsigned levels_ = 0;
  compute::Scanner scan_;
  compute::RadixSorter radix_;
};

}  // namespace ml
