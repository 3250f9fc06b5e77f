#pragma once
// Building a compute program in the project's two kernel shapes
// (host/cl/KernelShape.hpp), with the GPU shape's work-group size fitted to
// what the compiled kernels accept on the device:
//
//   FittedProgram p = buildFitted(env, tuning, "vct_mips.cl", "voxel mips");
//   cl::Kernel k(p.program, "mip_level");   // launch with p.wg items per group
//
// Used by the primitives here and by every pipeline above them that has its
// own kernels (voxel cone tracing).
#include <CL/opencl.hpp>

#include <cstddef>
#include <functional>

#include "host/cl/ProgramBuilder.hpp"
#include "host/compute/ComputeEnv.hpp"

namespace ml::compute {

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

}  // namespace ml::compute
