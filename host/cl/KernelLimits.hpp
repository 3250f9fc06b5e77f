#pragma once
// Device and kernel limits that a launch or an allocation must respect, in one
// place for the technique pipelines (tiled, clustered):
//
//   KernelShape s = resolveKernelShape(rt.info(), requested);     // Auto -> by device type
//   std::size_t local = fitLocalSize(kernel, rt, 256, 16 * 64, "cull_mark_wg");
//   launch1d(q, kernel, n, local, event);                          // global rounded up to local
//   cl::Buffer b = checkedBuffer(rt, CL_MEM_READ_WRITE, bytes, "tile light indices");
//
// fitLocalSize() queries CL_KERNEL_WORK_GROUP_SIZE, CL_KERNEL_LOCAL_MEM_SIZE and
// CL_DEVICE_LOCAL_MEM_SIZE: it returns the largest power of two <= the wanted
// size that the compiled kernel accepts (at least `min_local`), or throws
// UserError naming the kernel when even that does not fit. checkedBuffer()
// throws UserError when the bytes exceed CL_DEVICE_MAX_MEM_ALLOC_SIZE (the
// allocation would fail, or on some drivers succeed and fault later).
// Every launch over a data-dependent count passes an explicit local size: with
// NullRange a prime count leaves the driver local size 1, and the group size
// would change from frame to frame (the kernels guard i >= n).
#include <CL/opencl.hpp>

#include <cstddef>
#include <string>

#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelShape.hpp"

namespace ml {

// "auto" | "cpu" | "gpu"; UserError naming `flag` otherwise.
KernelShape parseKernelShape(const std::string& s, const std::string& flag = "--kernel-shape");
const char* kernelShapeName(KernelShape s);  // "auto" | "cpu" | "gpu"
// Auto: GpuWorkGroup on anything but a CPU device.
KernelShape resolveKernelShape(const DeviceInfo& info, KernelShape requested);

struct KernelLimits {
  std::size_t work_group_size = 0;   // CL_KERNEL_WORK_GROUP_SIZE
  cl_ulong kernel_local_mem = 0;     // CL_KERNEL_LOCAL_MEM_SIZE (static __local arrays)
  cl_ulong device_local_mem = 0;     // CL_DEVICE_LOCAL_MEM_SIZE
};
KernelLimits queryKernelLimits(const cl::Kernel& k, const cl::Device& d);

// Largest power of two in [min_local, want] that `k` runs with, given
// `local_bytes_per_item` of dynamic local memory per work-item on top of its
// static __local arrays. UserError (naming `what`) when none fits.
std::size_t fitLocalSize(const cl::Kernel& k, const cl::Device& d, std::size_t want, std::size_t min_local,
                         std::size_t local_bytes_per_item, const std::string& what);

// Local size of the per-element kernels that serve both shapes: 64 items on
// CPUs (PoCL loops over them, vectorized across items), 256 elsewhere, at least
// the kernel's CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE (whole SIMD
// bundles), at most `cap` when non-zero (tests force small groups), capped by
// the kernel's limit. On PoCL (2 cores) tile culling of 20,000 lights at
// 640x360 and 1280x720 took the same time with 16, 64, 256, 1024 and 4096
// items within the run-to-run noise (4 interleaved rounds, 2026-11-25).
std::size_t elementLocalSize(const cl::Kernel& k, const cl::Device& d, const DeviceInfo& info, std::size_t cap = 0);

// 1D launch over n items, global = n rounded up to `local`; nothing when n == 0.
void launch1d(cl::CommandQueue& q, const cl::Kernel& k, std::size_t n, std::size_t local, cl::Event* event);

// A cl::Buffer of max(bytes, 16) bytes, or UserError when `bytes` exceeds the
// device's maximum allocation.
cl::Buffer checkedBuffer(const ClRuntime& rt, cl_mem_flags flags, std::size_t bytes, const std::string& what);

}  // namespace ml
