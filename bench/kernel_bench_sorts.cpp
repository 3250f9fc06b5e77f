// The sort cases of the kernel bench (kernel_bench_cases.hpp): ours (radix,
// bitonic) and the peers (Boost.Compute on our queue, std::sort on one and on
// all cores), on the same keys, each checked against std::sort.
#include <algorithm>
#include <execution>

#include "host/compute/HostIo.hpp"
#include "kernel_bench_cases.hpp"

namespace ml::kbench {

using compute::download;

namespace {

std::string checkSorted(Bench& b, std::size_t n) {
  SizeInputs& in = b.inputs(n);
  return firstDifference("sorted keys", download<std::uint32_t>(b.q, in.work, n), in.sortedKeys());
}

void addRadix(Bench& b, std::size_t n) {
  auto restore = [&b, n] { b.inputs(n).restore(); };
  b.h.add(Case("radix_sort.u32", n, 8.0 * n)
              .before(restore)
              .run([&b, n] { b.radix.sort(b.q, b.inputs(n).work, nullptr, n, 32); })
              .checkedBy([&b, n] { return checkSorted(b, n); })
              .profiledBy([&b, n](ClPassTimer& t) { b.radix.sort(b.q, b.inputs(n).work, nullptr, n, 32, &t); })
              .counter("passes", double(b.radixPasses(n))));
  b.h.add(Case("radix_sort.u32_pairs", n, 16.0 * n)
              .before([&b, n] { b.inputs(n).restorePairs(); })
              .run([&b, n] { b.radix.sort(b.q, b.inputs(n).work, &b.inputs(n).vwork, n, 32); })
              .checkedBy([&b, n] {
                SizeInputs& in = b.inputs(n);
                return checkStablePairs(in.keys, download<std::uint32_t>(b.q, in.work, n),
                                        download<std::uint32_t>(b.q, in.vwork, n));
              }));
  b.h.add(Case("radix_sort.u64", n, 16.0 * n)
              .before([&b, n] {
                SizeInputs::Keys64& k = b.inputs(n).keys64();
                b.q.enqueueCopyBuffer(k.src, k.work, 0, 0, n * 8);
                b.q.finish();
              })
              .run([&b, n] { b.radix.sort64(b.q, b.inputs(n).keys64().work, nullptr, n, 64); })
              .checkedBy([&b, n] {
                SizeInputs::Keys64& k = b.inputs(n).keys64();
                return firstDifference("sorted 64-bit keys", download<std::uint64_t>(b.q, k.work, n), k.sorted);
              }));
}

void addDeviceSorts(Bench& b, std::size_t n) {
  auto restore = [&b, n] { b.inputs(n).restore(); };
  auto check = [&b, n] { return checkSorted(b, n); };
  b.h.add(Case("bitonic_sort.u32", n, 8.0 * n)
              .before(restore)
              .run([&b, n] { b.bitonic.sort(b.q, b.inputs(n).work, nullptr, n); })
              .checkedBy(check)
              .profiledBy([&b, n](ClPassTimer& t) { b.bitonic.sort(b.q, b.inputs(n).work, nullptr, n, &t); }));
  b.h.add(Case("boost_compute_sort.u32", n, 8.0 * n)
              .before(restore)
              .run([&b, n] { bench::boostComputeSortU32(b.q(), b.inputs(n).work(), n); })
              .checkedBy(check));
}

// The host sorts work in the size's host buffer (freed with the size's inputs).
void addHostSorts(Bench& b, std::size_t n) {
  auto fill = [&b, n] { std::copy(b.inputs(n).keys.begin(), b.inputs(n).keys.end(), b.inputs(n).hostOut().begin()); };
  auto check = [&b, n] {
    const HostWords& out = b.inputs(n).hostOut();
    return firstDifference("sorted keys", std::vector<std::uint32_t>(out.begin(), out.end()), b.inputs(n).sortedKeys());
  };
  b.h.add(Case("std_sort.u32", n, 8.0 * n)
              .onHost()
              .before(fill)
              .run([&b, n] { std::sort(b.inputs(n).hostOut().begin(), b.inputs(n).hostOut().end()); })
              .checkedBy(check));
  b.h.add(
      Case("std_sort_par.u32", n, 8.0 * n)
          .onHost()
          .before(fill)
          .run([&b, n] { std::sort(std::execution::par, b.inputs(n).hostOut().begin(), b.inputs(n).hostOut().end()); })
          .checkedBy(check));
}

}  // namespace

void addSortCases(Bench& b, std::size_t n) {
  addRadix(b, n);
  addDeviceSorts(b, n);
  addHostSorts(b, n);
}

}  // namespace ml::kbench
