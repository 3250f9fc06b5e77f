#pragma once
// Stable LSD radix sort of uint32 or uint64 keys with an optional uint32
// payload, in place (the result is in `keys` / `values`).
//
//   RadixSorter sorter(rt);
//   sorter.sort(q, keys, &values, n, 20);   // order by the low 20 key bits (e.g. cluster keys)
//   sorter.sort64(q, keys64, nullptr, n);    // Morton codes, all 64 bits
//   radix_sort(q, keys, &values, n, 32);     // free function, shared sorter per device
//
// Keys are ordered by their low `key_bits` bits only; higher bits travel with
// the key but do not take part (equal low bits keep input order). The cost is
// ceil(key_bits / digit) passes (digits up to 11 bits on the CPU shape, split
// evenly: 32 bits are 11 + 11 + 10), so pass the bits that matter. Each pass is
// reduce-then-scan (digit histogram per chunk, exclusive scan, scatter): no
// work-group ever waits on another, so it is portable to any OpenCL device.
// Digit width, work-group size and chunking come from device queries (see
// ComputeEnv.hpp). Enqueued on `q`, non-blocking. Temporary buffers (n keys,
// n values, counters; on CPU devices twice n keys and n values, in host memory
// on huge pages) are owned and grown by the object. Not thread-safe.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"
#include "host/compute/Scan.hpp"

namespace ml::compute {

class RadixSorter {
 public:
  explicit RadixSorter(ClRuntime& rt, const Options& options = {});
  explicit RadixSorter(const ComputeEnv& env, const Options& options = {});

  // uint32 keys; key_bits in 0..32 (0 sorts nothing).
  void sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits = 32,
            ClPassTimer* timer = nullptr);
  // uint64 keys; key_bits in 0..64.
  void sort64(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits = 64,
              ClPassTimer* timer = nullptr);

  // GPU shape: tuning().wg is what the 32-bit kernels run with (fitted to the
  // device on construction, buildFitted); the 64-bit ones are fitted
  // when first used, from there.
  const Tuning& tuning() const { return tuning_; }
  // The work-group size the GPU-shape kernels of that key width run with
  // (built on first use; 1 for the CPU shape).
  std::size_t workGroupSize(bool wide_keys = false);

 private:
  struct Variant {
    cl::Kernel hist, scatter;
    std::size_t wg = 1;
  };
  Variant& variant(bool wide);
  unsigned digitBits(std::size_t n) const;  // widest digit for n keys
  void sortImpl(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits,
                bool wide, ClPassTimer* timer);

  // The key / value ping-pong buffers. With host_pages (CPU shape on a CPU
  // device) they live in host memory the sorter allocates on transparent huge
  // pages where the OS offers them (see RadixSort.cpp); else a device buffer.
  class PassScratch {
   public:
    cl::Buffer& ensure(const ComputeEnv& env, std::size_t bytes, bool host_pages);

   private:
    detail::Scratch device_;
    cl::Buffer host_;
    std::size_t capacity_ = 0;
  };

  ComputeEnv env_;
  Options options_;
  Tuning tuning_;
  Scanner scanner_;
  Variant v32_, v64_;
  cl::Buffer dummy_;
  bool host_pages_ = false;
  PassScratch tmp_keys_, tmp_values_, tmp_keys2_, tmp_values2_;  // *2_: host pages only
  detail::Scratch counts_;
};

void radix_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits = 32);
void radix_sort64(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                  unsigned key_bits = 64);

}  // namespace ml::compute
