#pragma once
// One buffer that is both a GL buffer object and a cl::Buffer.
//
// GL and CL take turns: the owner of the frame calls acquireForCl() before
// kernels touch it and releaseToGl() before GL reads or writes it again. How
// the bytes move depends on the mode, chosen once per ClRuntime (shareMode()):
//  - Interop: cl_khr_gl_sharing (clCreateFromGLBuffer + acquire/release), GPUs.
//  - HostPtr: zero-copy where the device passes the zero-copy check (PoCL): the
//    GL buffer is persistently and coherently mapped, and the cl::Buffer wraps
//    that pointer (CL_MEM_USE_HOST_PTR).
//  - Copy: separate storage, copied at acquire/release as the access flags
//    need, only the bytes in use (setUsed()), not the growth headroom.
// $MANYLIGHTS_SHARE=interop|hostptr|copy forces a mode (tests use it).
// With a timer, acquire and release are named passes: `share-acquire` and
// `share-release` (the waits: glFinish, queue.finish) and `share-copy` (copy
// mode's transfers), so the pass table shows what moving the bytes costs.
// Depth and G-buffer images reach kernels through these buffers too (pack
// buffer reads: see readDepthInto()).
#include <CL/opencl.hpp>
#include <epoxy/gl.h>

#include <cstddef>
#include <string>

#include "host/cl/ClRuntime.hpp"
#include "host/util/PassTimings.hpp"

namespace ml {

enum class ClAccess { Read, Write, ReadWrite };

class SharedBuffer {
 public:
  SharedBuffer(ClRuntime& rt, std::size_t bytes, const std::string& label);
  SharedBuffer(ClRuntime& rt, std::size_t bytes, const std::string& label, ShareMode mode);
  ~SharedBuffer();
  SharedBuffer(const SharedBuffer&) = delete;
  SharedBuffer& operator=(const SharedBuffer&) = delete;

  GLuint gl() const { return gl_; }
  // Valid between acquireForCl() and releaseToGl() (interop objects are only
  // usable while acquired; other modes always are).
  cl::Buffer& cl() { return cl_; }
  std::size_t size() const { return bytes_; }
  ShareMode mode() const { return mode_; }
  const std::string& label() const { return label_; }

  // Reallocates when `bytes` exceeds the capacity (contents are lost). Returns
  // true if it reallocated. Never shrinks. Either way the first `bytes` are
  // then the bytes in use: all that copy mode moves at a hand-over.
  bool reserve(std::size_t bytes);
  std::size_t used() const { return used_; }

  // GL has finished with the buffer; kernels on `queue` may now use it.
  void acquireForCl(cl::CommandQueue& queue, ClAccess access);
  // Kernels are done (waits for `queue`); GL may now use the buffer.
  void releaseToGl(cl::CommandQueue& queue);

  // HostPtr mode: true when mapping the CL buffer yields the GL mapping's own
  // pointer, i.e. CL and GL really share the bytes (no hidden copy).
  bool verifyZeroCopy(cl::CommandQueue& queue);

  // Host writes/reads through GL (valid while GL owns the buffer).
  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;

 private:
  void allocate(std::size_t bytes);
  void release();
  void copyGlToCl(cl::CommandQueue& queue);
  void copyClToGl(cl::CommandQueue& queue);
  ClRuntime& rt_;
  std::string label_;
  ShareMode mode_;
  std::size_t bytes_ = 0;
  std::size_t used_ = 0;
  GLuint gl_ = 0;
  void* mapped_ = nullptr;  // HostPtr mode
  cl::Buffer cl_;
  bool acquired_ = false;
  ClAccess access_ = ClAccess::ReadWrite;
};

ShareMode defaultShareMode(const ClRuntime& rt);

}  // namespace ml
