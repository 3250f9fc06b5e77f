#pragma once
// `manylights devices`: every OpenCL platform with its vendor and version and
// the devices under it with the indices `--device N` takes, how each times its
// passes (its own profiling clock, or the host clock where that is unusable:
// ClPassTimer.hpp) and whether program binaries are cached on it
// (KernelCacheProbe.hpp); then what `render` would run on: the GL renderer,
// the CL device, whether they are the same device, and the share mode.
namespace ml {

int runDevices();

}  // namespace ml
