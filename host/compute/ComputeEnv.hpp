#pragma once
// Shared plumbing of the compute primitives (Scanner, Compactor, Reducer,
// RadixSorter, BitonicSorter, SegmentedSorter): the device they run on, the
// kernel shape, and the per-device tuning derived from device queries.
//
// Contract: every primitive has two kernel shapes and both are kept working and
// tested. CpuChunked: each work-item (local size 1) walks a contiguous chunk
// with private state, which PoCL runs like a plain C loop (up to 15x faster
// than local-memory atomics + barriers there). GpuWorkGroup: work-groups
// cooperate through local memory and barriers, which is what a GPU needs.
// Shape::Auto picks by CL_DEVICE_TYPE. No kernel spin-waits on another
// work-group; multi-pass designs are reduce-then-scan. The GPU shape's group
// size is compiled in (WG) and fitted per program to what its kernels accept
// on the device (CL_KERNEL_WORK_GROUP_SIZE, local memory; buildFitted):
// a size is lowered, never refused.
#include <CL/opencl.hpp>

#include <cstddef>
#include <memory>
#include <string>

#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelShape.hpp"
#include "host/cl/ProgramBuilder.hpp"

namespace ml::compute {

using Shape = KernelShape;  // host/cl/KernelShape.hpp

const char* shapeName(Shape s);

// Overrides of the device-derived tuning; zero means "from the device".
struct Options {
  Shape shape = Shape::Auto;
  // GpuWorkGroup: power of two <= CL_DEVICE_MAX_WORK_GROUP_SIZE, lowered
  // (with a note on stderr) to what each program's kernels accept.
  std::size_t work_group_size = 0;
  unsigned radix_bits = 0;          // radix sort's widest digit, 1..12 (default CPU 11, GPU 4)
  std::size_t chunks = 0;           // CpuChunked: most work-items per launch (default CUs * 8)
  std::size_t sort_chunk = 0;       // CpuChunked bitonic: power-of-two elements sorted per work-item in cache
};

// Resolved tuning (never Shape::Auto).
struct Tuning {
  Shape shape = Shape::CpuChunked;
  std::size_t wg = 1;            // GpuWorkGroup work-group size (first guess; see buildFitted)
  std::size_t requested_wg = 0;  // Options::work_group_size, 0 when from the device
  std::size_t items = 4;         // GpuWorkGroup elements per work-item in a tile
  std::size_t chunks = 16;       // CpuChunked work-items per launch (upper bound)
  std::size_t min_chunk = 4096;  // CpuChunked: no work-item gets fewer elements than this (unless n is smaller)
  // Most elements one work-item (CpuChunked) or work-group (GpuWorkGroup)
  // walks in one launch; 0: no bound. Set where the device ends long loops
  // early (llvmpipe: see loopBudgetChunk in ComputeEnv.cpp).
  std::size_t max_chunk = 0;
  unsigned radix_bits = 11;  // widest digit
  std::size_t cpu_sort_chunk = 1 << 13;  // CpuChunked bitonic: elements a work-item sorts in cache
  bool gpu() const { return shape == Shape::GpuWorkGroup; }
  // CpuChunked: number of work-items for n elements (>= 1) and each one's chunk.
  std::size_t cpuGroups(std::size_t n, std::size_t min_chunk_override = 0) const;
  std::size_t cpuChunk(std::size_t n, std::size_t min_chunk_override = 0) const;
};


// The device, context and program builder the primitives use. Cheap to copy.
class ComputeEnv {
 public:
  // Shares the runtime's program cache; the runtime must outlive the env.
  explicit ComputeEnv(ClRuntime& rt);
  // Stand-alone: own program builder (with the same on-disk binary cache).
  ComputeEnv(const cl::Context& context, const cl::Device& device);
  // A process-wide env for the context and device of `queue` (created once).
  static ComputeEnv forQueue(const cl::CommandQueue& queue);

  const cl::Context& context() const { return context_; }
  const cl::Device& device() const { return device_; }
  const DeviceInfo& info() const { return *info_; }
  ProgramBuilder& programs() const { return *programs_; }

 private:
  cl::Context context_;
  cl::Device device_;
  std::shared_ptr<const DeviceInfo> info_;
  std::shared_ptr<ProgramBuilder> programs_;
};

// Resolves `options` against the device queries (type, compute units, work-group
// and local memory limits, cache size). Throws std::invalid_argument on bad options.
Tuning resolveTuning(const ComputeEnv& env, const Options& options);

}  // namespace ml::compute
