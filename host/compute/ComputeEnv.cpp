#include "host/compute/ComputeEnv.hpp"

#include <algorithm>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/compute/Detail.hpp"
#include "host/util/Error.hpp"

namespace ml::compute {

namespace {

bool isPow2(std::size_t v) { return v && !(v & (v - 1)); }

// llvmpipe (Mesa rusticl's CPU device) ends a work-item's loops after 65,535
// iterations in total, all loops of the launch together, and the kernel goes
// on with wrong results (tests/driver/driver_loop_cap_test.cpp): the CPU-shape radix
// scatter of 16,400-key chunks lost the payload copy of its one-digit chunks.
// There the loops of the branch a work-item did not take run too, masked off
// (the copy path paid for the scatter loop), and chunks up to 13,120 keys
// came through while 16,144 did not (2^20 + 7 keys of 5 distinct values);
// 8,192 elements per work-item or group leave a margin. Elsewhere chunks stay
// unbounded: smaller ones would cost PoCL counters and scheduling for nothing.
std::size_t loopBudgetChunk(const DeviceInfo& info) {
  return info.name.find("llvmpipe") != std::string::npos ? std::size_t(8192) : 0;
}

}  // namespace

const char* shapeName(Shape s) {
  switch (s) {
    case Shape::Auto:
      return "auto";
    case Shape::CpuChunked:
      return "cpu-chunked";
    case Shape::GpuWorkGroup:
      return "gpu-workgroup";
  }
  return "?";
}

std::size_t Tuning::cpuGroups(std::size_t n, std::size_t min_chunk_override) const {
  return detail::ceilDiv(std::max<std::size_t>(n, 1), cpuChunk(n, min_chunk_override));
}

std::size_t Tuning::cpuChunk(std::size_t n, std::size_t min_chunk_override) const {
  const std::size_t minc = min_chunk_override ? min_chunk_override : min_chunk;
  std::size_t groups = std::clamp<std::size_t>(detail::ceilDiv(n, minc), 1, chunks);
  // max_chunk is a multiple of 16, so the rounding below stays within it.
  if (max_chunk) groups = std::max(groups, detail::ceilDiv(n, max_chunk));
  // Multiples of 16 elements keep every chunk start 64-byte aligned, so two
  // work-items never write the same cache line of a contiguous output.
  return detail::roundUp(detail::ceilDiv(std::max<std::size_t>(n, 1), groups), 16);
}

Tuning resolveTuning(const ComputeEnv& env, const Options& o) {
  const DeviceInfo& info = env.info();
  Tuning t;
  t.shape = o.shape != Shape::Auto ? o.shape : (info.isCpu() ? Shape::CpuChunked : Shape::GpuWorkGroup);

  if (o.work_group_size) {
    if (!isPow2(o.work_group_size) || o.work_group_size > info.max_work_group_size)
      throw std::invalid_argument("compute::Options::work_group_size must be a power of two <= the device maximum (" +
                                  std::to_string(info.max_work_group_size) + ")");
    t.wg = o.work_group_size;
    t.requested_wg = o.work_group_size;
  } else {
    // 256 fills a GPU compute unit without starving the local memory the
    // radix and bitonic tiles need; smaller devices get their maximum.
    t.wg = std::min<std::size_t>(256, detail::prevPow2(std::max<std::size_t>(info.max_work_group_size, 1)));
  }
  t.items = 4;
  const std::size_t cus = std::max<cl_uint>(info.compute_units, 1);
  // Eight work-items per compute unit: enough for dynamic balancing across
  // PoCL's worker threads, few enough that per-chunk bookkeeping (radix
  // histograms: 2^bits counters each) stays negligible.
  t.chunks = o.chunks ? o.chunks : cus * 8;
  t.min_chunk = 4096;
  t.max_chunk = loopBudgetChunk(info);

  if (o.radix_bits > 12) throw std::invalid_argument("compute::Options::radix_bits must be 1..12");
  // CPU: digits of up to 11 bits (3 passes for uint32 instead of 4; the scatter
  // is compute-bound there, so a pass saved is time saved; RadixSort.cpp uses
  // 8 bits below 2^16 keys, where 2^11 counters per chunk would dominate).
  // GPU: 4-bit digits keep the per-work-item digit counters of the local
  // ranking (2^bits * work-group size words) inside local memory.
  t.radix_bits = o.radix_bits ? o.radix_bits : (t.gpu() ? 4u : 11u);

  if (o.sort_chunk) {
    if (!isPow2(o.sort_chunk) || o.sort_chunk < 16)
      throw std::invalid_argument("compute::Options::sort_chunk must be a power of two >= 16");
    t.cpu_sort_chunk = o.sort_chunk;
  } else {
    // The chunk a work-item sorts runs ~log2(C)^2/2 passes over itself, so it
    // must stay in that core's private cache. OpenCL only reports the (shared,
    // last-level) global-memory cache; a 1/64 share of it per compute unit,
    // clamped to 16..128 KiB of keys+values, lands in a typical L2.
    const cl_ulong cache = env.device().getInfo<CL_DEVICE_GLOBAL_MEM_CACHE_SIZE>();
    const std::size_t bytes = std::clamp<std::size_t>(static_cast<std::size_t>(cache) / (cus * 64), 16 << 10, 128 << 10);
    t.cpu_sort_chunk = detail::prevPow2(bytes / 8);
  }
  return t;
}

ComputeEnv::ComputeEnv(ClRuntime& rt)
    : context_(rt.context()),
      device_(rt.device()),
      info_(std::make_shared<DeviceInfo>(rt.info())),
      programs_(&rt.programs(), [](ProgramBuilder*) {}) {}

ComputeEnv::ComputeEnv(const cl::Context& context, const cl::Device& device)
    : context_(context), device_(device), info_(std::make_shared<DeviceInfo>(queryDeviceInfo(device))) {
  programs_ = std::make_shared<ProgramBuilder>(context_, device_, *info_);
}

ComputeEnv ComputeEnv::forQueue(const cl::CommandQueue& queue) {
  static std::mutex mutex;
  // Never destroyed: releasing CL objects from static destructors can run after
  // the driver's own exit handlers.
  static auto* envs = new std::map<std::pair<cl_context, cl_device_id>, ComputeEnv>();
  cl::Context ctx = queue.getInfo<CL_QUEUE_CONTEXT>();
  cl::Device dev = queue.getInfo<CL_QUEUE_DEVICE>();
  std::lock_guard lock(mutex);
  auto key = std::make_pair(ctx(), dev());
  auto it = envs->find(key);
  if (it == envs->end()) it = envs->emplace(key, ComputeEnv(ctx, dev)).first;
  return it->second;
}

namespace detail {

cl::Buffer& Scratch::ensure(const ComputeEnv& env, std::size_t bytes) {
  bytes = std::max<std::size_t>(bytes, 4);
  if (bytes <= capacity_) return buf_;
  if (bytes > env.info().max_alloc_size)
    throw UserError("compute primitive needs a " + std::to_string(bytes) + "-byte scratch buffer; the device '" +
                    env.info().name + "' allocates at most " + std::to_string(env.info().max_alloc_size));
  // A quarter of headroom so slowly growing inputs do not reallocate each call.
  std::size_t grown = std::min<std::size_t>(bytes + bytes / 4, env.info().max_alloc_size);
  buf_ = cl::Buffer();  // release first: the old and new buffer need not coexist
  buf_ = cl::Buffer(env.context(), CL_MEM_READ_WRITE, grown);
  capacity_ = grown;
  return buf_;
}

}  // namespace detail
}  // namespace ml::compute
