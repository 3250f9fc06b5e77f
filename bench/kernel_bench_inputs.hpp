// One size's inputs for the kernel bench's cases and the C++ twins their
// outputs are checked against (kernel_bench_harness.hpp: each case checks its
// first run). Random uint32 keys (seed 12345 + n) and their indices on the
// device, work buffers the sorts restore before every run; the references
// (sorted keys, 64-bit keys) are made on first use, so a filtered run pays only
// for what its cases need.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <new>
#include <optional>
#include <string>
#include <vector>

namespace ml::kbench {

// Cache-line-aligned host words. glibc's memcpy on the AMD EPYC these
// results come from is ~28x slower when source and destination sit at different offsets
// within a cache line (2^16 words: 7.9 us at equal offsets, 220 us at +16
// bytes), so the host copy peer must not depend on where malloc put them.
template <class T>
struct LineAllocator {
  using value_type = T;
  LineAllocator() = default;
  template <class U>
  LineAllocator(const LineAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64))); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(64)); }
  bool operator==(const LineAllocator&) const { return true; }
};
using HostWords = std::vector<std::uint32_t, LineAllocator<std::uint32_t>>;

struct SizeInputs {
  SizeInputs(const cl::Context& ctx, cl::CommandQueue& q, std::size_t n, std::uint64_t seed);

  std::size_t n;
  cl::Context ctx;
  cl::CommandQueue& q;
  std::vector<std::uint32_t> keys;    // random
  cl::Buffer src, work, vsrc, vwork;  // keys, scratch, indices 0..n-1, scratch

  void restore();       // work = keys (blocking)
  void restorePairs();  // work = keys, vwork = indices (blocking)
  void poisonWork();    // work = 0xDEADBEEF words, so that an unwritten element shows

  const std::vector<std::uint32_t>& sortedKeys();  // std::sort of keys
  HostWords& hostSrc();  // the keys, line-aligned (the host copies' source)
  HostWords& hostOut();  // n line-aligned host words (the host copies' and sorts' output)
  cl::Buffer& oddFlags();                          // keys[i] & 1, on the device (compaction)
  // 64-bit random keys (seed 777 + n), on the device, with a work copy and their sort.
  struct Keys64 {
    std::vector<std::uint64_t> keys, sorted;
    cl::Buffer src, work;
  };
  Keys64& keys64();

 private:
  std::optional<std::vector<std::uint32_t>> sorted_;
  HostWords host_src_, host_out_;
  cl::Buffer odd_flags_;
  std::optional<Keys64> keys64_;
};

// "" when got == want (the first `n` elements), else "<what>: element i is x, expected y".
std::string firstDifference(const std::string& what, const std::vector<std::uint32_t>& got,
                            const std::vector<std::uint32_t>& want);
std::string firstDifference(const std::string& what, const std::vector<std::uint64_t>& got,
                            const std::vector<std::uint64_t>& want);

// "" when (keys, values) is `input` sorted stably by key with values = the
// original indices (a permutation of 0..n-1, ascending among equal keys).
std::string checkStablePairs(const std::vector<std::uint32_t>& input, const std::vector<std::uint32_t>& keys,
                             const std::vector<std::uint32_t>& values);

// "" when each segment [offsets[s], offsets[s + 1]) of (keys, values) holds
// the segment of `input` sorted by key, each value the index its key came
// from (segmented sorts are not stable, so equal keys may swap values).
std::string checkSegmentedPairs(const std::vector<std::uint32_t>& input, const std::vector<std::uint32_t>& offsets,
                                const std::vector<std::uint32_t>& keys, const std::vector<std::uint32_t>& values);

}  // namespace ml::kbench
