#pragma once
// Internal helpers of the compute primitives: grown scratch buffers, the
// process-wide shared objects, short names for the launch API. Not part of the
// API: code outside host/compute uses host/cl/Launch.hpp and
// host/compute/FittedProgram.hpp.
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
#include "host/cl/Launch.hpp"
#include "host/compute/ComputeEnv.hpp"
#include "host/compute/FittedProgram.hpp"

namespace ml::compute::detail {

using ml::ceilDiv;
using ml::roundUp;
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

// Argument checks and launches: the public ones of host/cl/Launch.hpp.
inline void checkBuffer(const cl::Buffer& buf, std::size_t bytes, const char* what) { requireBuffer(buf, bytes, what); }
inline void checkCount(std::size_t n, const char* what) { requireCount(n, what); }
using ml::sameBuffer;

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

inline void launch(cl::CommandQueue& q, const cl::Kernel& k, std::size_t global, std::size_t local,
                   ClPassTimer* timer, const char* name) {
  launchTimed(q, k, global, local, timer, name);
}

using ml::setArgs;

using ml::u32;

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
