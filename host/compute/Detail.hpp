#pragma once
// Internal helpers of the compute primitives: argument checks, grown scratch
// buffers, kernel launches with optional pass timing. Not part of the API.
#include <CL/opencl.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/KernelArgs.hpp"
#include "host/compute/ComputeEnv.hpp"

namespace ml::compute::detail {

inline std::size_t ceilDiv(std::size_t a, std::size_t b) { return (a + b - 1) / b; }
inline std::size_t roundUp(std::size_t a, std::size_t b) { return ceilDiv(a, b) * b; }
inline std::size_t nextPow2(std::size_t v) {
  std::size_t p = 1;
  while (p < v) p <<= 1;
  return p;
}
inline std::size_t prevPow2(std::size_t v) {
  std::size_t p = 1;
  while (p * 2 <= v) p <<= 1;
  return p;
}

// Throws std::invalid_argument when `buf` is smaller than `bytes` or n does not
// fit the 32-bit indices the kernels use.
void checkBuffer(const cl::Buffer& buf, std::size_t bytes, const char* what);
void checkCount(std::size_t n, const char* what);
bool sameBuffer(const cl::Buffer& a, const cl::Buffer& b);

// A device buffer that only grows. ensure() reallocates (dropping contents)
// when too small and throws UserError when the device cannot allocate that
// much, so a caller never works on a truncated buffer.
class Scratch {
 public:
  cl::Buffer& ensure(const ComputeEnv& env, std::size_t bytes);
  cl::Buffer& get() { return buf_; }
  std::size_t capacity() const { return capacity_; }

 private:
  cl::Buffer buf_;
  std::size_t capacity_ = 0;
};

// Enqueues a 1D range (global rounded up to local), timed under `name` when a
// timer is given.
void launch(cl::CommandQueue& q, const cl::Kernel& k, std::size_t global, std::size_t local, ClPassTimer* timer,
            const char* name);

using ml::setArgs;

// Builds kernels/<file> with the shape defines; returns the program.
cl::Program buildShaped(const ComputeEnv& env, const Tuning& t, const char* file, Defines extra = {});

// A program whose every kernel runs on this device with `wg` work-items per
// group (the WG it was compiled with; 1 for the CPU shape).
struct FittedProgram {
  cl::Program program;
  std::size_t wg = 1;
};
// Builds kernels/<file> as buildShaped() does, with `extra(wg)` on top. GPU
// shape: starts at t.wg; while a kernel of the program reports a
// CL_KERNEL_WORK_GROUP_SIZE below WG, or CL_KERNEL_LOCAL_MEM_SIZE over the
// device's local memory (its __local arrays scale with WG), rebuilds with the
// largest power of two that allows. The limits are per kernel and only known
// once compiled (rusticl's llvmpipe runs many of them with at most 32 items
// though the device says 1024), so no caller can pick a size beforehand and
// a too-large one is lowered, never refused: with one note on stderr when it
// lowers a size the caller asked for (t.requested_wg). UserError naming
// `what` when not even one work-item fits.
FittedProgram buildFitted(const ComputeEnv& env, const Tuning& t, const char* file, const char* what,
                          const std::function<Defines(std::size_t wg)>& extra = {});

// u32 helper: kernels index with uint.
inline cl_uint u32(std::size_t v) { return static_cast<cl_uint>(v); }

// The process-wide object behind a free-function wrapper: one T per (context,
// device) of `q`, built on first use and never destroyed (CL objects must not
// be released from static destructors). The returned lock serialises use.
template <class T>
struct Shared {
  std::unique_lock<std::mutex> lock;
  T& obj;
};

template <class T>
Shared<T> sharedFor(const cl::CommandQueue& q) {
  static std::mutex mutex;
  static auto* objects = new std::map<std::pair<cl_context, cl_device_id>, std::unique_ptr<T>>();
  ComputeEnv env = ComputeEnv::forQueue(q);
  std::unique_lock lock(mutex);
  auto& slot = (*objects)[{env.context()(), env.device()()}];
  if (!slot) slot = std::make_unique<T>(env);
  return {std::move(lock), *slot};
}

}  // namespace ml::compute::detail
