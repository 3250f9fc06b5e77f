#include "host/compute/RadixSort.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/util/Error.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

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

// CPU shape: below this many keys the digit stays at 8 bits; 2^11 counters
// per chunk would cost more than the pass they save.
constexpr std::size_t kWideDigitMinKeys = std::size_t(1) << 16;

// Host memory for a CPU device's scratch: 2 MiB-aligned and advised onto
// transparent huge pages. Each scatter pass writes 2^11 streams at once; on
// 4 KiB pages nearly every line it flushes lands on a page the TLB no longer
// holds, on 2 MiB pages the streams' pages all fit (about 1.3x per pass on
// the 2-core PoCL machine, same run). Null where the allocation fails; the
// OpenCL runtime frees the memory when it releases the buffer, so commands
// still queued on an old buffer keep it alive.
void CL_CALLBACK freeHostPages(cl_mem, void* p) { std::free(p); }

cl::Buffer hostPageBuffer(const ComputeEnv& env, std::size_t bytes) {
  constexpr std::size_t kPage = std::size_t(2) << 20;
  const std::size_t size = detail::roundUp(bytes, kPage);
  void* p = std::aligned_alloc(kPage, size);
  if (!p) return {};
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  madvise(p, size, MADV_HUGEPAGE);  // advice only: ignored where THP is off
#endif
  try {
    cl::Buffer b(env.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, size, p);
    b.setDestructorCallback(freeHostPages, p);
    return b;
  } catch (const cl::Error&) {
    std::free(p);
    return {};
  }
}

// Balanced digits: the fewest passes the widest digit allows, then the
// narrowest digit that still needs no more passes (20 key bits: 2 x 10, not
// 11 + 9), so that no pass pays for counters it does not use.
struct DigitPlan {
  unsigned passes, digit;
};
DigitPlan balancedDigits(unsigned key_bits, unsigned widest) {
  const unsigned passes = static_cast<unsigned>(ceilDiv(key_bits, widest));
  return {passes, static_cast<unsigned>(ceilDiv(key_bits, passes))};
}

// The keys each work-group (GPU shape) or work-item (CPU shape) counts and
// scatters, the local size, and how many chunks cover n keys.
struct Chunks {
  std::size_t chunk, local, groups;
};
Chunks chunksOf(const Tuning& t, std::size_t wg, const ComputeEnv& env, std::size_t n) {
  std::size_t chunk, local;
  if (t.gpu()) {
    const std::size_t tile = wg * t.items;
    const std::size_t tiles = ceilDiv(n, tile);
    // Enough groups to fill the device several times over, few enough that
    // the counter array (radix * groups) stays a small scan.
    const std::size_t max_groups = std::max<std::size_t>(env.info().compute_units, 1) * 8;
    std::size_t per_group = ceilDiv(tiles, std::min(tiles, max_groups));
    if (t.max_chunk) per_group = std::min(per_group, std::max<std::size_t>(t.max_chunk / tile, 1));
    chunk = per_group * tile;
    local = wg;
  } else {
    chunk = t.cpuChunk(n);
    local = 1;
  }
  return {chunk, local, ceilDiv(n, chunk)};
}

}  // namespace

cl::Buffer& RadixSorter::PassScratch::ensure(const ComputeEnv& env, std::size_t bytes, bool host_pages) {
  if (!host_pages || bytes > env.info().max_alloc_size) return device_.ensure(env, bytes);
  if (bytes <= capacity_) return host_;
  // A quarter of headroom, as detail::Scratch, so slowly growing inputs do
  // not reallocate each call.
  const std::size_t grown = std::min<std::size_t>(bytes + bytes / 4, env.info().max_alloc_size);
  host_ = cl::Buffer();  // release first: the old and new buffer need not coexist
  host_ = hostPageBuffer(env, grown);
  capacity_ = host_() ? grown : 0;
  return host_() ? host_ : device_.ensure(env, bytes);
}

unsigned RadixSorter::digitBits(std::size_t n) const {
  if (tuning_.gpu() || n >= kWideDigitMinKeys) return tuning_.radix_bits;
  return std::min(tuning_.radix_bits, 8u);
}

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
  host_pages_ = !tuning_.gpu() && env_.info().isCpu();
  // GPU shape: tuning() reports the group size the (common) 32-bit kernels
  // run with; the 64-bit ones start from it when first needed.
  if (tuning_.gpu()) tuning_.wg = variant(false).wg;
}

RadixSorter::Variant& RadixSorter::variant(bool wide) {
  Variant& v = wide ? v64_ : v32_;
  if (!v.hist()) {
    // Built on first use: most callers need only one key width.
    const FittedProgram p =
        buildFitted(env_, tuning_, "compute/radix_sort.cl", "radix sort", [&](std::size_t) -> Defines {
          return {{"KEY64", wide ? "1" : "0"}, {"RADIX_BITS", std::to_string(tuning_.radix_bits)}};
        });
    v.hist = cl::Kernel(p.program, "radix_hist");
    v.scatter = cl::Kernel(p.program, "radix_scatter");
    v.wg = p.wg;
  }
  return v;
}

std::size_t RadixSorter::workGroupSize(bool wide) { return variant(wide).wg; }

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
  const auto [passes, digit] = balancedDigits(key_bits, digitBits(n));
  const std::size_t radix = std::size_t(1) << tuning_.radix_bits;  // counters per chunk, widest digit
  const auto [chunk, local, groups] = chunksOf(tuning_, v.wg, env_, n);

  // Pass p writes into scratch p % 2. With host pages (CPU device) both are
  // scratch on huge pages, so no pass scatters into the caller's buffer
  // (4 KiB pages, see hostPageBuffer), and a copy returns the result; else the
  // passes ping-pong between the caller's buffer and one scratch, and only
  // an odd pass count needs the copy (cheaper than an extra pass).
  cl::Buffer vals = values ? *values : dummy_;
  cl::Buffer scratch_k[2] = {tmp_keys_.ensure(env_, n * key_bytes, host_pages_), keys};
  cl::Buffer scratch_v[2] = {values ? tmp_values_.ensure(env_, n * 4, host_pages_) : dummy_, vals};
  if (host_pages_ && passes > 1) {
    scratch_k[1] = tmp_keys2_.ensure(env_, n * key_bytes, true);
    if (values) scratch_v[1] = tmp_values2_.ensure(env_, n * 4, true);
  }
  cl::Buffer counts = counts_.ensure(env_, radix * groups * 4);

  cl::Buffer src_k = keys, src_v = vals;
  for (unsigned pass = 0; pass < passes; ++pass) {
    const unsigned shift = pass * digit;
    const unsigned bits = std::min(digit, key_bits - shift);
    const cl_uint mask = bits >= 32 ? 0xFFFFFFFFu : ((1u << bits) - 1u);
    detail::setArgs(v.hist, src_k, u32(n), u32(chunk), cl_uint(shift), mask, counts, u32(groups));
    detail::launch(q, v.hist, groups * local, local, timer, "radix.hist");
    // The CPU kernels count only the digits of this pass; the GPU kernels
    // count all 2^radix_bits (the unused ones stay zero).
    const std::size_t used = tuning_.gpu() ? radix : std::size_t(mask) + 1;
    scanner_.exclusive(q, counts, counts, used * groups, nullptr, timer);
    cl::Buffer& dst_k = scratch_k[pass % 2];
    cl::Buffer& dst_v = scratch_v[pass % 2];
    detail::setArgs(v.scatter, src_k, dst_k, src_v, dst_v, cl_uint(values != nullptr), u32(n), u32(chunk),
                    cl_uint(shift), mask, counts, u32(groups));
    detail::launch(q, v.scatter, groups * local, local, timer, "radix.scatter");
    src_k = dst_k;
    src_v = dst_v;
  }
  if (src_k() != keys()) {
    q.enqueueCopyBuffer(src_k, keys, 0, 0, n * key_bytes, nullptr, timer ? timer->next("radix.copy") : nullptr);
    if (values)
      q.enqueueCopyBuffer(src_v, *values, 0, 0, n * 4, nullptr, timer ? timer->next("radix.copy") : nullptr);
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
