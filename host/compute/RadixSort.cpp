#include "host/compute/RadixSort.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/util/Error.hpp"

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

namespace {

// Local memory of the work-group scatter kernel for `wg` work-items.
std::size_t scatterLocalBytes(const Tuning& t, std::size_t wg, std::size_t key_bytes) {
  const std::size_t radix = std::size_t(1) << t.radix_bits;
  const std::size_t tile = wg * t.items;
  return radix * wg * 4 + tile * (key_bytes + 4) + radix * 8 + wg * 4;
}

}  // namespace

RadixSorter::RadixSorter(ClRuntime& rt, const Options& options) : RadixSorter(ComputeEnv(rt), options) {}

RadixSorter::RadixSorter(const ComputeEnv& env, const Options& options)
    : env_(env), options_(options), tuning_(resolveTuning(env, options)), scanner_(env, options) {
  if (tuning_.gpu()) {
    // Shrink the work-group until the 64-bit-key scatter tile fits in local
    // memory (the per-(digit, work-item) counters dominate).
    while (tuning_.wg > 1 && scatterLocalBytes(tuning_, tuning_.wg, 8) > env_.info().local_mem_size)
      tuning_.wg /= 2;
    if (scatterLocalBytes(tuning_, tuning_.wg, 8) > env_.info().local_mem_size)
      throw UserError("radix sort: device '" + env_.info().name + "' has too little local memory (" +
                      std::to_string(env_.info().local_mem_size) + " bytes) for " +
                      std::to_string(tuning_.radix_bits) + "-bit digits; use Options::radix_bits or the CPU shape");
  }
  dummy_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, 16);
}

RadixSorter::Variant& RadixSorter::variant(bool wide) {
  Variant& v = wide ? v64_ : v32_;
  if (!v.hist()) {
    // Built on first use: most callers need only one key width.
    cl::Program p = detail::buildShaped(env_, tuning_, "radix_sort.cl",
                                        {{"KEY64", wide ? "1" : "0"},
                                         {"RADIX_BITS", std::to_string(tuning_.radix_bits)}});
    v.hist = cl::Kernel(p, "radix_hist");
    v.scatter = cl::Kernel(p, "radix_scatter");
    if (tuning_.gpu()) {
      const std::size_t max_wg = std::min(v.hist.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(env_.device()),
                                          v.scatter.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(env_.device()));
      if (max_wg < tuning_.wg)
        throw UserError("radix sort: the device runs these kernels with at most " + std::to_string(max_wg) +
                        " work-items per group, " + std::to_string(tuning_.wg) +
                        " configured; pass Options::work_group_size");
    }
  }
  return v;
}

void RadixSorter::sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits,
                       ClPassTimer* timer) {
  if (key_bits > 32) throw std::invalid_argument("RadixSorter::sort: key_bits must be 0..32");
  sortImpl(q, keys, values, n, key_bits, false, timer);
}

void RadixSorter::sort64(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                         unsigned key_bits, ClPassTimer* timer) {
  if (key_bits > 64) throw std::invalid_argument("RadixSorter::sort64: key_bits must be 0..64");
  sortImpl(q, keys, values, n, key_bits, true, timer);
}

void RadixSorter::sortImpl(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n,
                           unsigned key_bits, bool wide, ClPassTimer* timer) {
  const std::size_t key_bytes = wide ? 8 : 4;
  detail::checkCount(n, "RadixSorter");
  detail::checkBuffer(keys, n * key_bytes, "RadixSorter keys");
  if (values) {
    detail::checkBuffer(*values, n * 4, "RadixSorter values");
    if (detail::sameBuffer(keys, *values)) throw std::invalid_argument("RadixSorter: keys and values alias");
  }
  if (n < 2 || key_bits == 0) return;
  Variant& v = variant(wide);

  const unsigned digit = tuning_.radix_bits;
  const std::size_t radix = std::size_t(1) << digit;
  std::size_t groups, chunk, local;
  if (tuning_.gpu()) {
    const std::size_t tile = tuning_.wg * tuning_.items;
    const std::size_t tiles = ceilDiv(n, tile);
    // Enough groups to fill the device several times over, few enough that
    // the counter array (radix * groups) stays a small scan.
    const std::size_t max_groups = std::max<std::size_t>(env_.info().compute_units, 1) * 8;
    chunk = ceilDiv(tiles, std::min(tiles, max_groups)) * tile;
    local = tuning_.wg;
  } else {
    chunk = tuning_.cpuChunk(n);
    local = 1;
  }
  groups = ceilDiv(n, chunk);

  cl::Buffer tmp_keys = tmp_keys_.ensure(env_, n * key_bytes);
  cl::Buffer tmp_values = values ? tmp_values_.ensure(env_, n * 4) : dummy_;
  cl::Buffer counts = counts_.ensure(env_, radix * groups * 4);

  cl::Buffer src_k = keys, dst_k = tmp_keys;
  cl::Buffer src_v = values ? *values : dummy_, dst_v = tmp_values;
  const unsigned passes = static_cast<unsigned>(ceilDiv(key_bits, digit));
  for (unsigned pass = 0; pass < passes; ++pass) {
    const unsigned shift = pass * digit;
    const unsigned bits = std::min(digit, key_bits - shift);
    const cl_uint mask = bits >= 32 ? 0xFFFFFFFFu : ((1u << bits) - 1u);
    detail::setArgs(v.hist, src_k, u32(n), u32(chunk), cl_uint(shift), mask, counts, u32(groups));
    detail::launch(q, v.hist, groups * local, local, timer, "radix.hist");
    scanner_.exclusive(q, counts, counts, radix * groups, nullptr, timer);
    detail::setArgs(v.scatter, src_k, dst_k, src_v, dst_v, cl_uint(values != nullptr), u32(n), u32(chunk),
                    cl_uint(shift), mask, counts, u32(groups));
    detail::launch(q, v.scatter, groups * local, local, timer, "radix.scatter");
    std::swap(src_k, dst_k);
    std::swap(src_v, dst_v);
  }
  if (passes % 2 == 1) {
    // The result sits in the scratch buffers; an odd pass count is cheaper to
    // finish with a copy than with an extra, narrower pass.
    q.enqueueCopyBuffer(tmp_keys, keys, 0, 0, n * key_bytes, nullptr, timer ? timer->next("radix.copy") : nullptr);
    if (values)
      q.enqueueCopyBuffer(tmp_values, *values, 0, 0, n * 4, nullptr, timer ? timer->next("radix.copy") : nullptr);
  }
}

void radix_sort(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits) {
  auto s = detail::sharedFor<RadixSorter>(q);
  s.obj.sort(q, keys, values, n, key_bits);
}

void radix_sort64(cl::CommandQueue& q, cl::Buffer& keys, cl::Buffer* values, std::size_t n, unsigned key_bits) {
  auto s = detail::sharedFor<RadixSorter>(q);
  s.obj.sort64(q, keys, values, n, key_bits);
}

}  // namespace ml::compute
