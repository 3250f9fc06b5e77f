#pragma once
// Whether an OpenCL driver can be handed a program binary it does not accept
// without ending the process. PoCL returns CL_INVALID_BINARY or a build error;
// Mesa rusticl 22.x panics inside the driver ("unknown version") and the panic
// aborts the whole process (SIGABRT, exit 134). The binary cache
// (ProgramBuilder.hpp) only loads binaries on drivers that refuse safely: an
// entry with an intact header and checksum can still be one the driver
// refuses (a driver rebuilt under the same version strings), and such an
// entry must cost a recompile, never the user's run.
//
// Decided by a probe: a forked child process creates a context on the device
// and builds a program from 4096 zero bytes; the driver refuses safely when
// the child reports an error from the OpenCL calls and exits normally. A child
// that dies, accepts the bytes or does not finish within 30 s (a lock copied
// in the locked state by fork) counts as unsafe: then binaries are merely not
// cached. The answer is memoised per driver (`driver_key`: platform, device
// and driver versions) for the rest of the process.
// Test-only hook: $MANYLIGHTS_TEST_BINARIES=unsafe answers false (not memoised).
#include <CL/opencl.hpp>

#include <string>

namespace ml {

bool driverRefusesBinariesSafely(const cl::Device& device, const std::string& driver_key);

// Why binaries are not cached on a driver that cannot refuse them safely, for
// `manylights devices` and debug lines.
inline constexpr const char* kUnsafeBinariesReason =
    "not cached: the driver ends the process when it refuses a program binary";

}  // namespace ml
