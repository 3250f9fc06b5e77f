#pragma once
// The two shapes every kernel in this project comes in, chosen per device:
//   CpuChunked   a work-item walks a contiguous chunk with private state (PoCL
//                runs it like a plain C loop, up to 15x faster than local
//                atomics and barriers there);
//   GpuWorkGroup work-groups cooperate through local memory and barriers.
// Auto resolves by device type (resolveKernelShape, KernelLimits.hpp). It is
// declared here, at the bottom of the OpenCL layer, because the runtime's
// launch helpers and the compute primitives above it both name it.
namespace ml {

enum class KernelShape { Auto, CpuChunked, GpuWorkGroup };

}  // namespace ml
