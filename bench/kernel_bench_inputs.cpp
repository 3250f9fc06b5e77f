// Inputs and output checks of the kernel bench (kernel_bench_inputs.hpp).
#include "kernel_bench_inputs.hpp"

#include <algorithm>
#include <numeric>

#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"

namespace ml::kbench {

using compute::KeyDist;
using compute::makeKeys;
using compute::upload;

SizeInputs::SizeInputs(const cl::Context& context, cl::CommandQueue& queue, std::size_t count, std::uint64_t seed)
    : n(count), ctx(context), q(queue), keys(makeKeys<std::uint32_t>(count, KeyDist::Random, seed)) {
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  src = upload(ctx, q, keys);
  // Rounded up to whole uint4s: the copy kernel's last work-item reads one.
  const std::size_t bytes = std::max<std::size_t>((n + 3) / 4 * 16, 16);
  work = cl::Buffer(ctx, CL_MEM_READ_WRITE, bytes);
  vsrc = upload(ctx, q, values);
  vwork = cl::Buffer(ctx, CL_MEM_READ_WRITE, bytes);
}

void SizeInputs::restore() {
  q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
  q.finish();
}

void SizeInputs::restorePairs() {
  q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
  q.enqueueCopyBuffer(vsrc, vwork, 0, 0, n * 4);
  q.finish();
}

void SizeInputs::poisonWork() { compute::poison(q, work); }

const std::vector<std::uint32_t>& SizeInputs::sortedKeys() {
  if (!sorted_) {
    sorted_ = keys;
    std::sort(sorted_->begin(), sorted_->end());
  }
  return *sorted_;
}

HostWords& SizeInputs::hostSrc() {
  if (host_src_.size() != n) host_src_.assign(keys.begin(), keys.end());
  return host_src_;
}

HostWords& SizeInputs::hostOut() {
  if (host_out_.size() != n) host_out_.assign(n, 0xDEADBEEFu);
  return host_out_;
}

cl::Buffer& SizeInputs::oddFlags() {
  if (!odd_flags_()) {
    std::vector<std::uint32_t> f(n);
    for (std::size_t i = 0; i < n; ++i) f[i] = keys[i] & 1u;
    odd_flags_ = upload(ctx, q, f);
  }
  return odd_flags_;
}

SizeInputs::Keys64& SizeInputs::keys64() {
  if (!keys64_) {
    Keys64 k;
    k.keys = makeKeys<std::uint64_t>(n, KeyDist::Random, 777 + n);
    k.sorted = k.keys;
    std::sort(k.sorted.begin(), k.sorted.end());
    k.src = upload(ctx, q, k.keys);
    k.work = cl::Buffer(ctx, CL_MEM_READ_WRITE, std::max<std::size_t>(n, 1) * 8);
    keys64_ = std::move(k);
  }
  return *keys64_;
}

namespace {

template <class T>
std::string difference(const std::string& what, const std::vector<T>& got, const std::vector<T>& want) {
  if (got.size() != want.size())
    return what + ": " + std::to_string(got.size()) + " elements, expected " + std::to_string(want.size());
  const auto m = std::mismatch(got.begin(), got.end(), want.begin());
  if (m.first == got.end()) return "";
  return what + ": element " + std::to_string(m.first - got.begin()) + " is " + std::to_string(*m.first) +
         ", expected " + std::to_string(*m.second);
}

}  // namespace

std::string firstDifference(const std::string& what, const std::vector<std::uint32_t>& got,
                            const std::vector<std::uint32_t>& want) {
  return difference(what, got, want);
}

std::string firstDifference(const std::string& what, const std::vector<std::uint64_t>& got,
                            const std::vector<std::uint64_t>& want) {
  return difference(what, got, want);
}

std::string checkStablePairs(const std::vector<std::uint32_t>& input, const std::vector<std::uint32_t>& keys,
                             const std::vector<std::uint32_t>& values) {
  std::vector<bool> seen(input.size());
  for (std::size_t i = 0; i < input.size(); ++i) {
    const std::uint32_t v = values[i];
    const std::string at = "pair " + std::to_string(i);
    if (v >= input.size() || seen[v]) return at + ": value " + std::to_string(v) + " is not a new index";
    seen[v] = true;
    if (input[v] != keys[i])
      return at + ": key " + std::to_string(keys[i]) + " did not come with value " + std::to_string(v);
    if (i > 0 && keys[i - 1] > keys[i]) return at + ": keys out of order";
    if (i > 0 && keys[i - 1] == keys[i] && values[i - 1] > v) return at + ": equal keys swapped (not stable)";
  }
  return "";
}

std::string checkSegmentedPairs(const std::vector<std::uint32_t>& input, const std::vector<std::uint32_t>& offsets,
                                const std::vector<std::uint32_t>& keys, const std::vector<std::uint32_t>& values) {
  std::vector<bool> seen(input.size());
  for (std::size_t s = 0; s + 1 < offsets.size(); ++s) {
    const std::uint32_t lo = offsets[s], hi = offsets[s + 1];
    std::vector<std::uint32_t> want(input.begin() + lo, input.begin() + hi);
    std::sort(want.begin(), want.end());
    for (std::uint32_t i = lo; i < hi; ++i) {
      const std::uint32_t v = values[i];
      const std::string at = "segment " + std::to_string(s) + ", element " + std::to_string(i);
      if (keys[i] != want[i - lo])
        return at + ": key " + std::to_string(keys[i]) + ", expected " + std::to_string(want[i - lo]);
      if (v < lo || v >= hi || seen[v])
        return at + ": value " + std::to_string(v) + " is not a new index of the segment";
      seen[v] = true;
      if (input[v] != keys[i]) return at + ": key did not come with its value";
    }
  }
  return "";
}

}  // namespace ml::kbench
