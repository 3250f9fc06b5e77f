// SharedBuffer: GL writes, a CL kernel modifies in place, GL reads back, on the
// fallback paths that PoCL uses (zero-copy host pointer and explicit copies).
#include <gtest/gtest.h>

#include <random>

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/shared/test_shader_bindings.h"
#include "gl/SharedBuffer.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "support/TestDevice.hpp"
#include "support/TestGl.hpp"

namespace ml {
namespace {

// GL compute shaders do the GL-side writes and reads so the test exercises GL
// commands touching the buffer, not just host uploads.
constexpr const char* kKernel =
    "__kernel void scale_add(__global uint* a, uint n) { size_t i = get_global_id(0); if (i < n) a[i] = a[i] * 3u + 1u; }\n";

class SharedBufferTest : public ::testing::TestWithParam<ShareMode> {};

TEST_P(SharedBufferTest, RoundTripGlClGl) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (std::uint32_t n : {1u, 17u, 1000u, 65537u}) {
    SCOPED_TRACE("n=" + std::to_string(n));
    SharedBuffer buf(rt, n * sizeof(std::uint32_t), "test", GetParam());
    EXPECT_EQ(buf.mode(), GetParam());
    if (GetParam() == ShareMode::HostPtr && rt.info().isCpu()) {
      EXPECT_TRUE(buf.verifyZeroCopy(rt.queue()));
    }
    std::vector<std::uint32_t> input(n);
    for (auto& v : input) v = rng();

    // GL writes the input through a compute shader: out = in ^ key.
    const std::uint32_t key = rng();
    GLuint src = 0;
    glCreateBuffers(1, &src);
    glNamedBufferStorage(src, n * 4, input.data(), 0);
    ShaderProgram xor_prog({"test/test_xor.comp"});
    xor_prog.use();
    xor_prog.set("u_key", key);
    xor_prog.set("u_n", n);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_XOR_SRC, src);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_XOR_DST, buf.gl());
    glDispatchCompute((n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    glCheck("xor dispatch");

    // CL modifies in place.
    buf.acquireForCl(rt.queue(), ClAccess::ReadWrite);
    cl::Kernel k(rt.programs().buildSource("shared_buffer_test.cl", kKernel), "scale_add");
    k.setArg(0, buf.cl());
    k.setArg(1, n);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
    buf.releaseToGl(rt.queue());

    // GL reads it back through another compute pass (xor again) into a plain buffer.
    GLuint dst = 0;
    glCreateBuffers(1, &dst);
    std::vector<std::uint32_t> poison(n, 0xDEADBEEFu);
    glNamedBufferStorage(dst, n * 4, poison.data(), GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_XOR_SRC, buf.gl());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_TEST_XOR_DST, dst);
    glDispatchCompute((n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    std::vector<std::uint32_t> out(n);
    glGetNamedBufferSubData(dst, 0, n * 4, out.data());
    glCheck("read back");
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t expected = (((input[i] ^ key) * 3u + 1u) ^ key);
      ASSERT_EQ(out[i], expected) << "element " << i;
    }
    // Host download sees the CL result too.
    std::vector<std::uint32_t> host(n);
    buf.download(host.data(), n * 4);
    EXPECT_EQ(host[n - 1], (input[n - 1] ^ key) * 3u + 1u);
    glDeleteBuffers(1, &src);
    glDeleteBuffers(1, &dst);
  }
}

TEST_P(SharedBufferTest, ReserveGrowsAndKeepsWorking) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  SharedBuffer buf(rt, 16, "grow", GetParam());
  EXPECT_FALSE(buf.reserve(8));
  EXPECT_TRUE(buf.reserve(4096));
  EXPECT_GE(buf.size(), 4096u);
  std::vector<std::uint32_t> v(1024, 7u), back(1024, 0u);
  buf.upload(v.data(), 4096);
  buf.acquireForCl(rt.queue(), ClAccess::Read);
  rt.queue().enqueueReadBuffer(buf.cl(), CL_TRUE, 0, 4096, back.data());
  buf.releaseToGl(rt.queue());
  EXPECT_EQ(back, v);
  EXPECT_THROW(buf.upload(v.data(), buf.size() + 4), std::logic_error);
}

INSTANTIATE_TEST_SUITE_P(Fallbacks, SharedBufferTest, ::testing::Values(ShareMode::HostPtr, ShareMode::Copy),
                         [](const auto& info) { return shareModeName(info.param); });

TEST(SharedBuffer, DefaultModeOnThisDevice) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  const ShareMode m = defaultShareMode(rt);
  if (std::getenv("MANYLIGHTS_SHARE")) return;
  if (rt.glSharingActive()) EXPECT_EQ(m, ShareMode::Interop);
  else if (rt.zeroCopyHostPtr()) EXPECT_EQ(m, ShareMode::HostPtr);
  else EXPECT_EQ(m, ShareMode::Copy);
}

// Copy mode moves the bytes in use (the last reserve()), not the capacity with
// its growth headroom: bytes past them keep what CL had.
TEST(SharedBuffer, CopyModeMovesOnlyTheBytesInUse) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  cl::CommandQueue& q = rt.queue();
  SharedBuffer buf(rt, 4096, "in use", ShareMode::Copy);
  const std::size_t words = buf.size() / 4;
  std::vector<std::uint32_t> gl_words(words);
  for (std::size_t i = 0; i < words; ++i) gl_words[i] = std::uint32_t(i) * 2654435761u;
  buf.upload(gl_words.data(), buf.size());
  EXPECT_FALSE(buf.reserve(1000));  // in use: 1000 bytes, 250 words
  EXPECT_EQ(buf.used(), 1000u);
  q.enqueueFillBuffer(buf.cl(), 0xDEADBEEFu, 0, buf.size());
  buf.acquireForCl(q, ClAccess::ReadWrite);
  std::vector<std::uint32_t> cl_words(words);
  q.enqueueReadBuffer(buf.cl(), CL_TRUE, 0, buf.size(), cl_words.data());
  for (std::size_t i = 0; i < words; ++i)
    ASSERT_EQ(cl_words[i], i < 250 ? gl_words[i] : 0xDEADBEEFu) << "word " << i;
  // Back to GL: CL writes every word, GL receives the words in use only.
  q.enqueueFillBuffer(buf.cl(), 7u, 0, buf.size());
  buf.releaseToGl(q);
  std::vector<std::uint32_t> back(words);
  buf.download(back.data(), buf.size());
  for (std::size_t i = 0; i < words; ++i) ASSERT_EQ(back[i], i < 250 ? 7u : gl_words[i]) << "word " << i;
}

// With a sink set (the frame renderer sets one per frame), hand-overs are
// named passes: waits as share-acquire/-release, copy mode's transfers as share-copy.
TEST(SharedBuffer, HandOversAreNamedPasses) {
  test::glContext();
  ClRuntime& rt = test::runtime();
  for (ShareMode mode : {ShareMode::HostPtr, ShareMode::Copy}) {
    SCOPED_TRACE(shareModeName(mode));
    SharedBuffer buf(rt, 4096, "timed", mode);
    PassTimings t;
    rt.setShareTimings(&t);
    buf.acquireForCl(rt.queue(), ClAccess::ReadWrite);
    buf.releaseToGl(rt.queue());
    rt.setShareTimings(nullptr);
    buf.acquireForCl(rt.queue(), ClAccess::ReadWrite);  // not timed
    buf.releaseToGl(rt.queue());
    std::vector<std::string> names;
    for (const auto& [n, ms] : t.entries()) {
      names.push_back(n);
      EXPECT_GE(ms, 0.0);
    }
    const std::vector<std::string> want =
        mode == ShareMode::Copy ? std::vector<std::string>{"share-copy", "share-release"}
                                : std::vector<std::string>{"share-acquire", "share-release"};
    EXPECT_EQ(names, want);
  }
}

}  // namespace
}  // namespace ml
