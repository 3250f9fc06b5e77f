#pragma once
// setArgs(k, a, b, c) sets a kernel's arguments 0, 1, 2, ... in one call, so
// an argument list reads like the kernel's signature and cannot skip an index.
#include <CL/opencl.hpp>

namespace ml {

template <typename... Args>
void setArgs(cl::Kernel& k, const Args&... args) {
  cl_uint i = 0;
  (k.setArg(i++, args), ...);
}

}  // namespace ml
