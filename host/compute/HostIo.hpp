#pragma once
// Small host<->device helpers for the primitives' callers, tests and
// benchmarks: blocking upload/download of std::vector, and poisoning a buffer
// so that a kernel that forgets to write an element is caught.
#include <CL/opencl.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ml::compute {

// A new buffer holding `data` (at least 4 bytes, so n == 0 still gives a valid handle).
template <class T>
cl::Buffer upload(const cl::Context& ctx, cl::CommandQueue& q, const std::vector<T>& data,
                  std::size_t extra_elements = 0) {
  const std::size_t bytes = std::max<std::size_t>((data.size() + extra_elements) * sizeof(T), 4);
  cl::Buffer buf(ctx, CL_MEM_READ_WRITE, bytes);
  if (!data.empty()) q.enqueueWriteBuffer(buf, CL_TRUE, 0, data.size() * sizeof(T), data.data());
  return buf;
}

template <class T>
void write(cl::CommandQueue& q, cl::Buffer& buf, const std::vector<T>& data) {
  if (!data.empty()) q.enqueueWriteBuffer(buf, CL_TRUE, 0, data.size() * sizeof(T), data.data());
}

template <class T>
std::vector<T> download(cl::CommandQueue& q, const cl::Buffer& buf, std::size_t n) {
  std::vector<T> out(n);
  if (n) q.enqueueReadBuffer(buf, CL_TRUE, 0, n * sizeof(T), out.data());
  return out;
}

// Fills the whole buffer with 0xDEADBEEF words (blocking).
inline void poison(cl::CommandQueue& q, cl::Buffer& buf) {
  const std::size_t bytes = buf.getInfo<CL_MEM_SIZE>();
  q.enqueueFillBuffer(buf, cl_uint(0xDEADBEEFu), 0, bytes / 4 * 4);
  q.finish();
}

}  // namespace ml::compute
