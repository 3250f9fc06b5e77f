// Two defects of Mesa rusticl 22.3 (Debian 12), each shown with the fewest
// OpenCL calls that exhibit it. Named expected failures: on rusticl each test
// passes while the driver is wrong and turns red once a fixed driver behaves
// as OpenCL says, so the workaround can be reconsidered; on every other
// implementation they check the behaviour the workaround relies on.
//  - Profiling events carry constants (START 2, END 3, in ns) instead of
//    times: every pass would read 0.000 ms. Workaround: ClPassTimer probes the
//    clock once per device and times passes on the host clock, bracketed by
//    finish calls (host/cl/ClPassTimer.hpp).
//  - Handed a program binary it does not accept, it panics inside the driver
//    and the panic aborts the whole process (SIGABRT) where the specification
//    asks for CL_INVALID_BINARY. Workaround: binaries are not cached on a
//    driver that a forked probe sees die (host/cl/KernelCacheProbe.hpp).
#include <gtest/gtest.h>

#include <CL/opencl.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "support/TestDevice.hpp"

namespace {

bool onRusticl() { return ml::test::runtime().info().platform_name.find("rusticl") != std::string::npos; }

TEST(DriverDefect, RusticlProfilingEventsCarryConstantsNotTimes) {
  ml::ClRuntime& rt = ml::test::runtime();
  const std::size_t bytes = std::size_t(64) << 20;  // a fill of 64 MiB takes milliseconds anywhere
  cl::Buffer buf(rt.context(), CL_MEM_READ_WRITE, bytes);
  cl::CommandQueue q(rt.context(), rt.device(), CL_QUEUE_PROFILING_ENABLE);
  cl::Event e;
  q.enqueueFillBuffer(buf, cl_uint(7), 0, bytes, nullptr, &e);
  e.wait();
  const cl_ulong start = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
  const cl_ulong end = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
  if (onRusticl()) {
    EXPECT_LT(end - start, 1000u) << "driver defect fixed? start " << start << " ns, end " << end
                                  << " ns: reconsider the host-clock fallback for rusticl";
  } else {
    EXPECT_GT(end, start + 1000u) << "a 64 MiB fill that took under a microsecond: start " << start << ", end " << end;
  }
}

// In a child: a context on the test device, a program from 4096 zero bytes,
// a build. Exit 0 when the driver refused with an error, 1 when it accepted.
[[noreturn]] void buildJunkBinaryAndExit(const cl::Device& device) {
  try {
    cl::Context ctx(device);
    const cl::Program::Binaries junk{std::vector<unsigned char>(4096, 0)};
    std::vector<cl_int> status;
    cl::Program program(ctx, {device}, junk, &status);
    program.build({device});
  } catch (const cl::Error&) {
    ::_exit(0);
  }
  ::_exit(1);
}

TEST(DriverDefect, RusticlAbortsTheProcessOnARefusedProgramBinary) {
  const cl::Device device = ml::test::runtime().device();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) buildJunkBinaryAndExit(device);
  // A lock copied in the locked state by fork could hang the child: 30 s at most.
  int status = 0;
  pid_t done = 0;
  for (int i = 0; i < 300 && done == 0; ++i) {
    done = ::waitpid(pid, &status, WNOHANG);
    if (done == 0) ::usleep(100000);
  }
  if (done == 0) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    FAIL() << "the child building a junk binary did not finish in 30 s";
  }
  ASSERT_EQ(done, pid);
  if (onRusticl()) {
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT)
        << "driver defect fixed? the child " << (WIFEXITED(status) ? "exited " + std::to_string(WEXITSTATUS(status))
                                                                   : "died otherwise")
        << ": reconsider caching binaries on rusticl";
  } else {
    ASSERT_TRUE(WIFEXITED(status)) << "the driver ended the process on a refused binary (signal "
                                   << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the driver accepted 4096 zero bytes as a program binary";
  }
}

}  // namespace
