#pragma once
// Prefix sums of uint32 (wrapping mod 2^32), any n, in place allowed.
//
//   Scanner scan(rt);
//   scan.exclusive(q, in, out, n);                  // out[i] = in[0] + ... + in[i-1]
//   scan.inclusive(q, in, out, n, &total_buf);       // out[i] = in[0] + ... + in[i]; total -> total_buf[0]
//   uint32_t t = scan.exclusiveTotal(q, in, out, n); // blocks for the total
//
// Reduce-then-scan: per-chunk sums, a scan of those sums, then each chunk
// scanned from its offset. CPU shape: one work-item per contiguous chunk
// (compute units x 8 chunks), the sums scanned by one work-item. GPU shape: one
// work-group per tile of work-group-size x 4 elements, the tile sums scanned
// recursively by the same kernels (multi-level for large n). No work-group
// waits on another. Calls are enqueued on `q` and do not block unless they
// return a value. Temporary buffers are owned and grown by the object. Not
// thread-safe: one object per thread.
#include <CL/opencl.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/Detail.hpp"

namespace ml::compute {

enum class ScanKind { Exclusive, Inclusive };

class Scanner {
 public:
  explicit Scanner(ClRuntime& rt, const Options& options = {});
  explicit Scanner(const ComputeEnv& env, const Options& options = {});

  // Scans in[0, n) into out[0, n). `total`, when given, receives the sum of all
  // n elements at uint index `total_index` (0 for n == 0).
  void scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n, ScanKind kind,
            cl::Buffer* total = nullptr, std::size_t total_index = 0, ClPassTimer* timer = nullptr);
  void exclusive(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n,
                 cl::Buffer* total = nullptr, ClPassTimer* timer = nullptr) {
    scan(q, in, out, n, ScanKind::Exclusive, total, 0, timer);
  }
  void inclusive(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n,
                 cl::Buffer* total = nullptr, ClPassTimer* timer = nullptr) {
    scan(q, in, out, n, ScanKind::Inclusive, total, 0, timer);
  }
  // Exclusive scan that waits for and returns the total.
  std::uint32_t exclusiveTotal(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n,
                               ClPassTimer* timer = nullptr);

  const Tuning& tuning() const { return tuning_; }

 private:
  void level(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n, bool inclusive,
             std::size_t depth, cl::Buffer* total, std::size_t total_index, ClPassTimer* timer);

  ComputeEnv env_;
  Tuning tuning_;
  cl::Kernel reduce_, tiles_;
  cl::Buffer dummy_;
  std::vector<detail::Scratch> partials_;  // one per recursion level
  detail::Scratch total_;
};

// Convenience wrappers: a process-wide Scanner per (context, device) of `q`,
// default options; calls are serialised on a lock.
void exclusive_scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n);
void inclusive_scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n);

}  // namespace ml::compute
