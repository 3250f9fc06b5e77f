#pragma once
// Cluster keys and unique clusters on the device (kernels/clustered/cluster_keys.cl):
//
//   ClusterUniquer u(rt, UniqueMethod::PageTable);
//   u.keys(q, depth, cam, grid);             // per-pixel keys into keyBuffer()
//   uint32_t c = u.unique(q, grid);           // blocks for the count
//   // uniqueKeys()[0, c): ascending keys; clusterOf()[pixel]: index into them
//   // or kClusterInvalid for sky
//
// The three methods give identical outputs (same order, same map):
//   PageTable  virtual page table over the key space (Karas): mark used pages,
//              scan the marks into physical page numbers, flag the used slots
//              of the physical pages, compact the slot flags;
//   Sort       radix sort of (key, pixel) on keyBits() + 1 bits, run heads,
//              scan, scatter;
//   TileSort   per-tile bitonic sort of (key, pixel) (segments = tiles, as
//              nTiled did on the CPU), then as Sort.
// unique() may also run on keys written by the caller into keyBuffer()
// (setKeys), which is how the tests reach every bit field's limits.
// Buffers are owned and grown; not thread-safe.
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
#include "host/compute/SegmentedSort.hpp"

namespace ml {

enum class UniqueMethod { PageTable, Sort, TileSort };
UniqueMethod parseUniqueMethod(const std::string& s);  // "pagetable" | "sort" | "tile-sort"; UserError
const char* uniqueMethodName(UniqueMethod m);

class ClusterUniquer {
 public:
  // max_group: most work-items per group of every kernel, the compute
  // primitives' included (0: what the device allows each kernel; tests force
  // 32 .. the device maximum).
  ClusterUniquer(ClRuntime& rt, UniqueMethod method, unsigned page_bits = 6, KernelShape shape = KernelShape::Auto,
                 std::size_t max_group = 0);

  // depth: window floats (cam.width x cam.height, row 0 bottom).
  void keys(cl::CommandQueue& q, const cl::Buffer& depth, const gpu::CameraParams& cam, const ClusterGrid& g,
            ClPassTimer* timer = nullptr);
  // Uploads caller keys (width * height of the grid) instead of keys().
  void setKeys(cl::CommandQueue& q, const std::vector<std::uint32_t>& keys, const ClusterGrid& g);
  // map_out, when given (width * height uints, e.g. a SharedBuffer for the
  // shader), receives the pixel -> cluster map instead of clusterOf().
  std::uint32_t unique(cl::CommandQueue& q, const ClusterGrid& g, ClPassTimer* timer = nullptr,
                       cl::Buffer* map_out = nullptr);

  const cl::Buffer& keyBuffer() const { return keys_; }
  const cl::Buffer& uniqueKeys() const { return unique_keys_; }
  const cl::Buffer& clusterOf() const { return cluster_of_; }
  UniqueMethod method() const { return method_; }
  KernelShape shape() const { return shape_; }  // resolved, never Auto
  void setMethod(UniqueMethod m) { method_ = m; }
  std::size_t scratchBytes() const;

 private:
  void ensurePixels(std::size_t n);
  std::uint32_t uniquePageTable(cl::CommandQueue& q, const ClusterGrid& g, std::size_t n, ClPassTimer* timer,
                                cl::Buffer& map);
  std::uint32_t uniqueSorted(cl::CommandQueue& q, const ClusterGrid& g, std::size_t n, bool per_tile,
                             ClPassTimer* timer, cl::Buffer& map);

  ClRuntime& rt_;
  UniqueMethod method_;
  KernelShape shape_;
  std::size_t local_ = 1;  // every kernel here is one work-item per element
  unsigned page_bits_;
  cl::Program program_;
  cl::Kernel keys_k_, mark_, store_, inverse_, page_unique_, page_map_, sort_init_, gather_, heads_, scatter_;
  cl::Buffer keys_, unique_keys_, cluster_of_, sort_keys_, sort_vals_, flags_, rank_;
  cl::Buffer marks_, page_table_, phys_to_virt_, slots_, used_slots_, bounds_, tile_offsets_;
  std::size_t pixel_capacity_ = 0, page_capacity_ = 0, slot_capacity_ = 0, bounds_capacity_ = 0;
  std::size_t tile_offsets_capacity_ = 0;
  unsigned offsets_for_w_ = 0, offsets_for_h_ = 0, offsets_for_tile_ = 0;
  compute::Scanner scan_;
  compute::Compactor compact_;
  compute::RadixSorter radix_;
  compute::SegmentedSorter segsort_;
};

}  // namespace ml
