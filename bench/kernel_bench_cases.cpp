// The copy peers and the scan / reduce / compaction cases of the kernel bench
// (kernel_bench_cases.hpp), and the state the cases share.
#include "kernel_bench_cases.hpp"

#include <algorithm>
#include <cstring>
#include <execution>
#include <memory>
#include <numeric>

#include "host/compute/HostIo.hpp"

namespace ml::kbench {

using compute::download;

namespace {

// The OpenCL copy kernel of the copy bound: one uint4 per work-item (the
// fastest shape measured on PoCL, pocl-performance.md, and the usual one on
// GPUs); the last work-item copies the n % 4 tail element by element.
const char* kCopySource = R"CL(
__kernel void copy4(__global const uint4* restrict a, __global uint4* restrict b, uint n) {
  const size_t i = get_global_id(0);
  if (4 * i + 3 < n) {
    b[i] = a[i];
    return;
  }
  __global const uint* as = (__global const uint*)a;
  __global uint* bs = (__global uint*)b;
  for (size_t j = 4 * i; j < n; ++j) bs[j] = as[j];
}
)CL";

}  // namespace

Bench::Bench(ClRuntime& runtime, Harness& harness, const compute::Options& options)
    : rt(runtime),
      h(harness),
      q(runtime.queue()),
      tune(options),
      radix(runtime, options),
      bitonic(runtime, options),
      scanner(runtime, options),
      reducer(runtime, options),
      compactor(runtime, options),
      segsort(runtime, options),
      copy4(runtime.programs().buildSource("bench_copy.cl", kCopySource), "copy4") {}

SizeInputs& Bench::inputs(std::size_t n) {
  return slot.get<SizeInputs>({0, n}, [&] { return std::make_unique<SizeInputs>(rt.context(), q, n, 12345 + n); });
}

unsigned Bench::radixPasses(std::size_t n) const {
  const unsigned digit = radix.tuning().radix_bits;
  const unsigned used = n >= (1u << 16) || radix.tuning().gpu() ? digit : std::min(digit, 8u);
  return (32 + used - 1) / used;
}

namespace {

// Host copies: one core, and both cores in 1 MiB blocks over TBB's pool (the
// std::execution::par backend).
void addHostCopies(Bench& b, std::size_t n) {
  auto poison = [&b, n] { std::fill(b.inputs(n).hostOut().begin(), b.inputs(n).hostOut().end(), 0xDEADBEEFu); };
  auto check = [&b, n] {
    const HostWords& out = b.inputs(n).hostOut();
    return firstDifference("copy", std::vector<std::uint32_t>(out.begin(), out.end()), b.inputs(n).keys);
  };
  b.h.add(Case("copy.host_memcpy", n, 8.0 * n)
              .onHost()
              .before(poison)
              .run([&b, n] { std::memcpy(b.inputs(n).hostOut().data(), b.inputs(n).hostSrc().data(), n * 4); })
              .checkedBy(check));
  b.h.add(Case("copy.host_memcpy_par", n, 8.0 * n)
              .onHost()
              .before(poison)
              .run([&b, n] {
                constexpr std::size_t block = 1u << 18;
                std::uint32_t* out = b.inputs(n).hostOut().data();
                const std::uint32_t* in = b.inputs(n).hostSrc().data();
                std::vector<std::size_t> starts;
                for (std::size_t i = 0; i < n; i += block) starts.push_back(i);
                std::for_each(std::execution::par, starts.begin(), starts.end(),
                              [&](std::size_t i) { std::memcpy(out + i, in + i, std::min(block, n - i) * 4); });
              })
              .checkedBy(check));
}

std::string checkWorkIsKeys(Bench& b, std::size_t n) {
  SizeInputs& in = b.inputs(n);
  return firstDifference("copy", download<std::uint32_t>(b.q, in.work, n), in.keys);
}

void addDeviceCopies(Bench& b, std::size_t n) {
  b.h.add(Case("copy.cl_enqueue_copy", n, 8.0 * n)
              .before([&b, n] { b.inputs(n).poisonWork(); })
              .run([&b, n] { b.q.enqueueCopyBuffer(b.inputs(n).src, b.inputs(n).work, 0, 0, n * 4); })
              .checkedBy([&b, n] { return checkWorkIsKeys(b, n); }));
  b.h.add(Case("copy.cl_kernel_uint4", n, 8.0 * n)
              .before([&b, n] { b.inputs(n).poisonWork(); })
              .run([&b, n] {
                SizeInputs& in = b.inputs(n);
                b.copy4.setArg(0, in.src);
                b.copy4.setArg(1, in.work);
                b.copy4.setArg(2, cl_uint(n));
                b.q.enqueueNDRangeKernel(b.copy4, cl::NullRange, cl::NDRange(std::max<std::size_t>((n + 3) / 4, 1)));
              })
              .checkedBy([&b, n] { return checkWorkIsKeys(b, n); }));
}

void addScanReduce(Bench& b, std::size_t n) {
  b.h.add(Case("scan.exclusive.u32", n, 8.0 * n)
              .before([&b, n] { b.inputs(n).poisonWork(); })
              .run([&b, n] { b.scanner.exclusive(b.q, b.inputs(n).src, b.inputs(n).work, n); })
              .checkedBy([&b, n] {
                SizeInputs& in = b.inputs(n);
                std::vector<std::uint32_t> want(n);
                std::exclusive_scan(in.keys.begin(), in.keys.end(), want.begin(), 0u);
                return firstDifference("exclusive scan", download<std::uint32_t>(b.q, in.work, n), want);
              })
              .profiledBy([&b, n](ClPassTimer& t) {
                b.scanner.exclusive(b.q, b.inputs(n).src, b.inputs(n).work, n, nullptr, &t);
              }));
  auto sum = std::make_shared<std::uint32_t>(0);
  b.h.add(Case("reduce.sum.u32", n, 4.0 * n)
              .before([sum] { *sum = 0xDEADBEEFu; })
              .run([&b, n, sum] {
                *sum = b.reducer.reduce<std::uint32_t>(b.q, b.inputs(n).src, n, compute::ReduceOp::Sum);
              })
              .checkedBy([&b, n, sum] {
                const std::uint32_t want = std::accumulate(b.inputs(n).keys.begin(), b.inputs(n).keys.end(), 0u);
                return *sum == want ? std::string()
                                    : "sum " + std::to_string(*sum) + ", expected " + std::to_string(want);
              }));
}

// Compaction keeps the odd keys (about half), in order.
void addCompact(Bench& b, std::size_t n) {
  auto kept = std::make_shared<std::size_t>(0);
  b.h.add(Case("compact.half.u32", n, 12.0 * n)
              .before([&b, n] {
                b.inputs(n).oddFlags();
                b.inputs(n).poisonWork();
              })
              .run([&b, n, kept] {
                SizeInputs& in = b.inputs(n);
                *kept = b.compactor.compact(b.q, in.src, in.oddFlags(), in.work, n);
              })
              .checkedBy([&b, n, kept] {
                std::vector<std::uint32_t> want;
                for (std::uint32_t k : b.inputs(n).keys)
                  if (k & 1u) want.push_back(k);
                return firstDifference("compaction", download<std::uint32_t>(b.q, b.inputs(n).work, *kept), want);
              }));
}

}  // namespace

void addSizeCases(Bench& b, std::size_t n) {
  addHostCopies(b, n);
  addDeviceCopies(b, n);
  addSortCases(b, n);
  addScanReduce(b, n);
  addCompact(b, n);
}

}  // namespace ml::kbench
