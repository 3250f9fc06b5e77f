#pragma once
// Stable stream compaction of uint32 elements and unique on sorted keys.
//
//   Compactor c(rt);
//   size_t k = c.compact(q, in, flags, out, n);     // out[0,k) = in[i] with flags[i] != 0, in order
//   size_t k = c.compactIndices(q, flags, out, n);  // out[0,k) = the i with flags[i] != 0, ascending
//   size_t u = c.unique(q, sorted_keys, out, n);    // first element of each run of equal keys
//   c.compactAsync(q, in, flags, out, n, count_buf); // no wait: count -> count_buf[0]
//
// `out` must hold n elements (the worst case) and must not alias the inputs;
// elements of `out` past the count are left unspecified. The value-returning
// forms wait for the count; the *Async forms only enqueue. Reduce-then-scan:
// count per chunk, scan, write. Not thread-safe: one object per thread.
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"
#include "host/compute/Scan.hpp"

namespace ml::compute {

class Compactor {
 public:
  explicit Compactor(ClRuntime& rt, const Options& options = {});
  explicit Compactor(const ComputeEnv& env, const Options& options = {});

  std::size_t compact(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                      std::size_t n, ClPassTimer* timer = nullptr);
  std::size_t compactIndices(cl::CommandQueue& q, const cl::Buffer& flags, cl::Buffer& out, std::size_t n,
                             ClPassTimer* timer = nullptr);
  std::size_t unique(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n,
                     ClPassTimer* timer = nullptr);

  // The count goes to count[count_index] (uint32) on the device.
  void compactAsync(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                    std::size_t n, cl::Buffer& count, std::size_t count_index = 0, ClPassTimer* timer = nullptr);
  void compactIndicesAsync(cl::CommandQueue& q, const cl::Buffer& flags, cl::Buffer& out, std::size_t n,
                           cl::Buffer& count, std::size_t count_index = 0, ClPassTimer* timer = nullptr);
  void uniqueAsync(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n,
                   cl::Buffer& count, std::size_t count_index = 0, ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }

 private:
  enum class Mode { Values, Indices, Unique };
  // Enqueues everything; the count ends at counts_[groups], whose index is returned.
  std::size_t run(cl::CommandQueue& q, Mode mode, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                  std::size_t n, ClPassTimer* timer);
  std::size_t readCount(cl::CommandQueue& q, std::size_t index);
  void copyCount(cl::CommandQueue& q, std::size_t index, cl::Buffer& count, std::size_t count_index);

  ComputeEnv env_;
  Tuning tuning_;
  Scanner scanner_;
  cl::Kernel compact_count_, unique_count_, compact_write_, unique_write_;
  detail::Scratch counts_;
};

std::size_t compact(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                    std::size_t n);
std::size_t unique(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n);

}  // namespace ml::compute
