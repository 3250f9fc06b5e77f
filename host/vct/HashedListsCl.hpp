#pragma once
// The hashed structure's light lists as OpenCL buffers, for kernels that
// look lights up in world space (kernels/hashed/hashed_lookup.cl, the OpenCL port of
// lookup_hashed.glsl). upload() writes what hashed::GpuUploadPlan says (the
// rules of the GL copy, HashedAssigner): the whole image
// (LinklessOctree::packGpuImage() and the light index list) after a build or a
// layout change, else only what an update edited; buffers grow and never
// truncate. upload() takes the octree's edit records, so one structure feeds
// one HashedListsCl at a time (another one is uploaded with `rebuilt`).
// Camera-independent: a lookup works anywhere in the octree's bounds, on
// screen or not, which is why voxel injection can use these lists and not
// the view-space tiled/clustered ones.
#include <CL/opencl.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "host/compute/ComputeEnv.hpp"
#include "host/hashed/GpuUploadPlan.hpp"
#include "host/hashed/LinklessOctree.hpp"

namespace ml::vct {

class HashedListsCl {
 public:
  explicit HashedListsCl(const compute::ComputeEnv& env);

  // `rebuilt`: the octree is new since the last upload (HashedStructure::build,
  // or an update that rebuilt); then everything is written.
  void upload(cl::CommandQueue& q, hashed::LinklessOctree& octree, bool rebuilt);
  bool empty() const { return !uploaded_; }
  std::size_t lastUploadBytes() const { return upload_bytes_; }
  bool lastUploadWasFull() const { return upload_full_; }
  // Reads the buffers back against the octree's image word for word: ""
  // when equal, else the first stale array's name (tests).
  std::string staleArray(cl::CommandQueue& q, const hashed::LinklessOctree& octree) const;

  // Sets kernel arguments first .. first + 4: header, offsets, desc, data, list.
  void setArgs(cl::Kernel& k, cl_uint first) const;

  // Test probe (hashed_lookup_probe): per point, (offset, count, octant) as
  // LinklessOctree::lookup() returns them.
  std::vector<hashed::LinklessOctree::Range> lookup(cl::CommandQueue& q, const std::vector<gpu::ml_float4>& points);

  std::size_t bytes() const;

 private:
  struct Grown {
    cl::Buffer buf;
    std::size_t capacity = 0;
  };
  void grow(Grown& g, std::size_t words);

  compute::ComputeEnv env_;
  Grown header_, offsets_, desc_, data_, list_;  // capacity in bytes
  hashed::GpuUploadPlanner planner_;
  bool uploaded_ = false, upload_full_ = false;
  std::size_t upload_bytes_ = 0;
  cl::Kernel probe_;
};

}  // namespace ml::vct
