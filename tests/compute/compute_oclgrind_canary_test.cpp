// Canaries for scripts/oclgrind.sh: kernels with seeded bugs (a missing
// barrier, a read of a buffer nobody wrote, a read past the end) that Oclgrind
// must report, and correct kernels in the two host-side patterns that Oclgrind
// 21.10's uninitialized-value checker got wrong (see scripts/oclgrind.sh) that
// it must not report. The script reads Oclgrind's log by kernel name; these
// tests only launch the kernels and check what a correct device computes.
// They run only with MANYLIGHTS_OCLGRIND_CANARY=1 (the buggy kernels read out
// of bounds, which on a real device is undefined).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "host/compute/HostIo.hpp"
#include "support/TestDevice.hpp"

namespace ml::compute {
namespace {

constexpr std::size_t kWg = 64;

const char* kSource = R"CL(
/* Missing barrier between the local store and the neighbour's load. */
__kernel void canary_local_race(__global const uint* in, __global uint* out) {
  __local uint tmp[64];
  const uint lid = get_local_id(0);
  tmp[lid] = in[get_global_id(0)];
  out[get_global_id(0)] = tmp[(lid + 1) % 64];
}

/* `in` is a buffer that neither the host nor a kernel ever wrote. */
__kernel void canary_uninitialized_read(__global const uint* in, __global uint* out) {
  out[get_global_id(0)] = in[get_global_id(0)];
}

/* The last work-item reads in[n]. */
__kernel void canary_out_of_bounds(__global const uint* in, __global uint* out) {
  out[get_global_id(0)] = in[get_global_id(0) + 1];
}

__kernel void canary_clean_write(__global uint* buf, uint n) {
  const uint i = get_global_id(0);
  if (i < n) buf[i] = i * 3u;
}

/* Through local memory, so that an uninitialized value would be reported. */
__kernel void canary_clean_copy(__global const uint* in, __global uint* out, uint n) {
  __local uint tmp[64];
  const uint i = get_global_id(0), lid = get_local_id(0);
  tmp[lid] = i < n ? in[i] : 0u;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (i < n) out[i] = tmp[lid];
}
)CL";

class ComputeOclgrindCanary : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* env = std::getenv("MANYLIGHTS_OCLGRIND_CANARY");
    if (!env || std::string(env) != "1") GTEST_SKIP() << "only under scripts/oclgrind.sh";
    program_ = cl::Program(test::runtime().context(), kSource);
    program_.build({test::runtime().device()}, "-cl-std=CL1.2");
  }

  void launch(const char* name, std::size_t items, const cl::Buffer& a, const cl::Buffer& b) {
    cl::Kernel k(program_, name);
    k.setArg(0, a);
    k.setArg(1, b);
    test::runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NDRange(kWg));
  }

  void launchN(const char* name, std::size_t n, const cl::Buffer& a, const cl::Buffer* b) {
    cl::Kernel k(program_, name);
    k.setArg(0, a);
    if (b) k.setArg(1, *b);
    k.setArg(b ? 2 : 1, static_cast<cl_uint>(n));
    const std::size_t items = (n + kWg - 1) / kWg * kWg;
    test::runtime().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NDRange(kWg));
  }

  cl::Program program_;
};

TEST_F(ComputeOclgrindCanary, SeededBugs) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  std::vector<std::uint32_t> v(2 * kWg);
  std::iota(v.begin(), v.end(), 1u);
  cl::Buffer in = upload(rt.context(), q, v);
  cl::Buffer never_written(rt.context(), CL_MEM_READ_WRITE, v.size() * 4);
  cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, v.size() * 4);
  launch("canary_local_race", v.size(), in, out);
  launch("canary_uninitialized_read", v.size(), never_written, out);
  launch("canary_out_of_bounds", v.size(), in, out);
  q.finish();
}

// A buffer released and a larger one created (Oclgrind reuses the index), both
// written by a kernel only, then read by a kernel.
TEST_F(ComputeOclgrindCanary, CleanAfterReleaseAndRegrow) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  for (const std::size_t n : {kWg, 4 * kWg}) {
    cl::Buffer buf(rt.context(), CL_MEM_READ_WRITE, n * 4), out(rt.context(), CL_MEM_READ_WRITE, n * 4);
    launchN("canary_clean_write", n, buf, nullptr);
    launchN("canary_clean_copy", n, buf, &out);
    const auto got = download<std::uint32_t>(q, out, n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], i * 3u) << "n=" << n << " i=" << i;
  }
}

// A buffer written by the host in two parts (a prefix, then a fill of the
// rest), then read by a kernel.
TEST_F(ComputeOclgrindCanary, CleanAfterPartialHostWrites) {
  auto& rt = test::runtime();
  auto& q = rt.queue();
  const std::size_t n = 100;
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 7u);
  cl::Buffer buf = upload(rt.context(), q, v, 1);
  q.enqueueFillBuffer(buf, cl_uint(0xDEADBEEFu), n * 4, 4);
  cl::Buffer out(rt.context(), CL_MEM_READ_WRITE, (n + 1) * 4);
  launchN("canary_clean_copy", n + 1, buf, &out);
  v.push_back(0xDEADBEEFu);
  EXPECT_EQ(download<std::uint32_t>(q, out, n + 1), v);
}

}  // namespace
}  // namespace ml::compute
