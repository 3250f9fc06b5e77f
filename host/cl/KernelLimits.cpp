#include "host/cl/KernelLimits.hpp"

#include <algorithm>

#include "host/util/Error.hpp"

namespace ml {

KernelShape parseKernelShape(const std::string& s, const std::string& flag) {
  if (s == "auto") return KernelShape::Auto;
  if (s == "cpu") return KernelShape::CpuChunked;
  if (s == "gpu") return KernelShape::GpuWorkGroup;
  throw UserError(flag + ": expected auto, cpu or gpu, got '" + s + "'");
}

const char* kernelShapeName(KernelShape s) {
  switch (s) {
    case KernelShape::Auto: return "auto";
    case KernelShape::CpuChunked: return "cpu";
    case KernelShape::GpuWorkGroup: return "gpu";
  }
  return "?";
}

KernelShape resolveKernelShape(const DeviceInfo& info, KernelShape requested) {
  if (requested != KernelShape::Auto) return requested;
  return info.isCpu() ? KernelShape::CpuChunked : KernelShape::GpuWorkGroup;
}

KernelLimits queryKernelLimits(const cl::Kernel& k, const cl::Device& d) {
  KernelLimits l;
  l.work_group_size = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(d);
  l.kernel_local_mem = k.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(d);
  l.device_local_mem = d.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
  return l;
}

std::size_t fitLocalSize(const cl::Kernel& k, const cl::Device& d, std::size_t want, std::size_t min_local,
                         std::size_t local_bytes_per_item, const std::string& what) {
  const KernelLimits l = queryKernelLimits(k, d);
  std::size_t local = 1;
  while (local * 2 <= want) local *= 2;
  auto fits = [&](std::size_t s) {
    return s <= l.work_group_size && l.kernel_local_mem + cl_ulong(s) * local_bytes_per_item <= l.device_local_mem;
  };
  while (local > min_local && !fits(local)) local /= 2;
  if (local < min_local || !fits(local))
    throw UserError("kernel " + what + " needs work-groups of " + std::to_string(min_local) + " items and " +
                    std::to_string(l.kernel_local_mem + cl_ulong(min_local) * local_bytes_per_item) +
                    " bytes of local memory; the device allows " + std::to_string(l.work_group_size) + " items and " +
                    std::to_string(l.device_local_mem) + " bytes (use --kernel-shape cpu)");
  return local;
}

std::size_t elementLocalSize(const cl::Kernel& k, const cl::Device& d, const DeviceInfo& info, std::size_t cap) {
  const std::size_t multiple = k.getWorkGroupInfo<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(d);
  std::size_t want = std::max<std::size_t>(info.isCpu() ? 64 : 256, multiple);
  if (cap) want = std::min(want, cap);
  return fitLocalSize(k, d, want, 1, 0, k.getInfo<CL_KERNEL_FUNCTION_NAME>());
}

void launch1d(cl::CommandQueue& q, const cl::Kernel& k, std::size_t n, std::size_t local, cl::Event* event) {
  if (n == 0) return;
  const std::size_t global = (n + local - 1) / local * local;
  q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(local), nullptr, event);
}

cl::Buffer checkedBuffer(const ClRuntime& rt, cl_mem_flags flags, std::size_t bytes, const std::string& what) {
  if (bytes > rt.info().max_alloc_size)
    throw UserError(what + " needs a " + std::to_string(bytes) + "-byte buffer; the device '" + rt.info().name +
                    "' allocates at most " + std::to_string(rt.info().max_alloc_size) +
                    " (fewer lights or a smaller --size)");
  return cl::Buffer(rt.context(), flags, std::max<std::size_t>(bytes, 16));
}

}  // namespace ml
