#pragma once
// The hashed structure's light lists as OpenCL buffers, for kernels that
// look lights up in world space (kernels/hashed_lookup.cl, the OpenCL port of
// lookup_hashed.glsl). upload() copies the whole image
// (LinklessOctree::packGpuImage() and the light index list); buffers grow and
// never truncate. Camera-independent: a lookup works anywhere in the
// octree's bounds, on screen or not, which is why voxel injection can use
// these lists and not the view-space tiled/clustered ones.
#include <CL/opencl.hpp>

#include <cstdint>
#include <vector>

#include "host/compute/ComputeEnv.hpp"
#include "host/hashed/LinklessOctree.hpp"

namespace ml::vct {

class HashedListsCl {
 public:
  explicit HashedListsCl(const compute::ComputeEnv& env);

  void upload(cl::CommandQueue& q, const hashed::LinklessOctree& octree);
  bool empty() const { return !uploaded_; }

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
  void put(cl::CommandQueue& q, Grown& g, const std::vector<std::uint32_t>& words);

  compute::ComputeEnv env_;
  Grown header_, offsets_, desc_, data_, list_;
  bool uploaded_ = false;
  cl::Kernel probe_;
};

}  // namespace ml::vct
