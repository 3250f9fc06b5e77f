#pragma once
// The launch API every kernel host above host/cl uses (compute primitives,
// technique pipelines, voxel cone tracing):
//
//   requireCount(n, "voxel inject");                  // n fits the kernels' 32-bit indices
//   requireBuffer(buf, n * 16, "voxel inject: volume");
//   setArgs(k, buf, u32(n));                         // KernelArgs.hpp
//   launchTimed(q, k, n, local, timer, "vct_inject"); // global rounded up to local; timed when timer
//
// requireCount/requireBuffer throw std::invalid_argument: they guard a
// caller's contract (a programming error), not user input. launchTimed
// enqueues nothing for n == 0, and takes an explicit local size: with
// NullRange a prime count leaves the driver local size 1 (KernelLimits.hpp).
#include <CL/opencl.hpp>

#include <cstddef>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/KernelArgs.hpp"

namespace ml {

inline std::size_t ceilDiv(std::size_t a, std::size_t b) { return (a + b - 1) / b; }
inline std::size_t roundUp(std::size_t a, std::size_t b) { return ceilDiv(a, b) * b; }
// Kernels index with uint.
inline cl_uint u32(std::size_t v) { return static_cast<cl_uint>(v); }

void requireCount(std::size_t n, const char* what);
void requireBuffer(const cl::Buffer& buf, std::size_t bytes, const char* what);
bool sameBuffer(const cl::Buffer& a, const cl::Buffer& b);

void launchTimed(cl::CommandQueue& q, const cl::Kernel& k, std::size_t global, std::size_t local, ClPassTimer* timer,
                 const char* name);

}  // namespace ml
