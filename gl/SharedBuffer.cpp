#include "gl/SharedBuffer.hpp"

#include <CL/cl_gl.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "gl/GlCheck.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/util/Error.hpp"

namespace ml {

// Decided once per runtime (ClRuntime::create: sharing, zero-copy check, $MANYLIGHTS_SHARE).
ShareMode defaultShareMode(const ClRuntime& rt) { return rt.shareMode(); }

SharedBuffer::SharedBuffer(ClRuntime& rt, std::size_t bytes, const std::string& label)
    : SharedBuffer(rt, bytes, label, defaultShareMode(rt)) {}

SharedBuffer::SharedBuffer(ClRuntime& rt, std::size_t bytes, const std::string& label, ShareMode mode)
    : rt_(rt), label_(label), mode_(mode) {
  allocate(bytes);
  used_ = bytes;
}

SharedBuffer::~SharedBuffer() { release(); }

void SharedBuffer::release() {
  cl_ = cl::Buffer();
  if (gl_) {
    if (mapped_) glUnmapNamedBuffer(gl_);
    glDeleteBuffers(1, &gl_);
  }
  gl_ = 0;
  mapped_ = nullptr;
}

void SharedBuffer::allocate(std::size_t bytes) {
  // Zero-sized CL buffers are invalid; keep a minimum so "no lights" is a normal case.
  bytes_ = bytes < 16 ? 16 : (bytes + 15) / 16 * 16;
  if (bytes_ > rt_.info().max_alloc_size)
    throw UserError("buffer '" + label_ + "' needs " + std::to_string(bytes_) + " bytes, more than the device's " +
                    "max allocation of " + std::to_string(rt_.info().max_alloc_size));
  glCreateBuffers(1, &gl_);
  glObjectLabel(GL_BUFFER, gl_, -1, label_.c_str());
  try {
    switch (mode_) {
      case ShareMode::Interop: {
        glNamedBufferStorage(gl_, static_cast<GLsizeiptr>(bytes_), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glCheck(("allocating shared buffer " + label_).c_str());
        glFinish();
        cl_int err = CL_SUCCESS;
        cl_ = cl::BufferGL(rt_.context(), CL_MEM_READ_WRITE, gl_, &err);
        break;
      }
      case ShareMode::HostPtr: {
        const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
        glNamedBufferStorage(gl_, static_cast<GLsizeiptr>(bytes_), nullptr, flags | GL_DYNAMIC_STORAGE_BIT);
        mapped_ = glMapNamedBufferRange(gl_, 0, static_cast<GLsizeiptr>(bytes_), flags);
        glCheck(("mapping shared buffer " + label_).c_str());
        if (!mapped_) throw std::runtime_error("glMapNamedBufferRange returned null for " + label_);
        cl_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes_, mapped_);
        break;
      }
      case ShareMode::Copy: {
        glNamedBufferStorage(gl_, static_cast<GLsizeiptr>(bytes_), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glCheck(("allocating shared buffer " + label_).c_str());
        cl_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, bytes_);
        break;
      }
    }
  } catch (const cl::Error& e) {
    throw std::runtime_error("creating the CL side of shared buffer '" + label_ + "' (" + shareModeName(mode_) +
                             "): " + describeClError(e));
  }
}

bool SharedBuffer::reserve(std::size_t bytes) {
  if (acquired_) throw std::logic_error("SharedBuffer::reserve while acquired by CL: " + label_);
  used_ = bytes;
  if (bytes <= bytes_) return false;
  release();
  // Grow geometrically so per-frame growth (more lights in view) settles fast.
  allocate(bytes + bytes / 2);
  return true;
}

namespace {

double nowMs() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Times one hand-over step on the host clock into the runtime's share timings
// (set by the frame renderer around a timed frame; null otherwise).
template <typename F>
void timed(ClRuntime& rt, const char* pass, F&& step) {
  PassTimings* sink = rt.shareTimings();
  const double t0 = sink ? nowMs() : 0.0;
  step();
  if (sink) sink->add(pass, nowMs() - t0, PassClock::Host);
}

}  // namespace

// Copy mode: the bytes in use, GL -> host -> CL (blocking: the host vector dies here).
void SharedBuffer::copyGlToCl(cl::CommandQueue& queue) {
  if (used_ == 0) return;
  std::vector<unsigned char> tmp(used_);
  glGetNamedBufferSubData(gl_, 0, static_cast<GLsizeiptr>(used_), tmp.data());
  glCheck(("reading shared buffer " + label_).c_str());
  queue.enqueueWriteBuffer(cl_, CL_TRUE, 0, used_, tmp.data());
}

void SharedBuffer::copyClToGl(cl::CommandQueue& queue) {
  if (used_ == 0) return;
  std::vector<unsigned char> tmp(used_);
  queue.enqueueReadBuffer(cl_, CL_TRUE, 0, used_, tmp.data());
  glNamedBufferSubData(gl_, 0, static_cast<GLsizeiptr>(used_), tmp.data());
  glCheck(("writing shared buffer " + label_).c_str());
}

// share-acquire / share-release time the waits on the host clock: they include
// device work still in flight (which its own pass counts too), so they show
// what each hand-over holds the pipeline up, not extra device work.
void SharedBuffer::acquireForCl(cl::CommandQueue& queue, ClAccess access) {
  if (acquired_) throw std::logic_error("SharedBuffer acquired twice: " + label_);
  access_ = access;
  switch (mode_) {
    case ShareMode::Interop:
      timed(rt_, "share-acquire", [&] {
        glFinish();  // portable: GL must be done before clEnqueueAcquireGLObjects
        std::vector<cl::Memory> objs{cl_};
        queue.enqueueAcquireGLObjects(&objs);
      });
      break;
    case ShareMode::HostPtr:
      // Coherent persistent mapping: once GL's commands completed, the bytes are in place.
      timed(rt_, "share-acquire", [] { glFinish(); });
      break;
    case ShareMode::Copy:
      if (access != ClAccess::Write) timed(rt_, "share-copy", [&] { copyGlToCl(queue); });
      break;
  }
  acquired_ = true;
}

void SharedBuffer::releaseToGl(cl::CommandQueue& queue) {
  if (!acquired_) throw std::logic_error("SharedBuffer released without acquire: " + label_);
  switch (mode_) {
    case ShareMode::Interop:
      timed(rt_, "share-release", [&] {
        std::vector<cl::Memory> objs{cl_};
        queue.enqueueReleaseGLObjects(&objs);
        queue.finish();
      });
      break;
    case ShareMode::HostPtr:
      timed(rt_, "share-release", [&] { queue.finish(); });
      break;
    case ShareMode::Copy:
      // The wait for the kernels first, so that share-copy is the copy alone.
      timed(rt_, "share-release", [&] { queue.finish(); });
      if (access_ != ClAccess::Read) timed(rt_, "share-copy", [&] { copyClToGl(queue); });
      break;
  }
  acquired_ = false;
}

bool SharedBuffer::verifyZeroCopy(cl::CommandQueue& queue) {
  if (mode_ != ShareMode::HostPtr) return false;
  void* p = queue.enqueueMapBuffer(cl_, CL_TRUE, CL_MAP_READ, 0, bytes_);
  queue.enqueueUnmapMemObject(cl_, p);
  queue.finish();
  return p == mapped_;
}

void SharedBuffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  if (offset + bytes > bytes_) throw std::logic_error("SharedBuffer::upload past the end of " + label_);
  if (bytes == 0) return;
  if (mode_ == ShareMode::HostPtr) {
    glFinish();  // GL may still be reading the previous contents
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
  } else {
    glNamedBufferSubData(gl_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
    glCheck(("uploading to " + label_).c_str());
  }
}

void SharedBuffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  if (offset + bytes > bytes_) throw std::logic_error("SharedBuffer::download past the end of " + label_);
  if (bytes == 0) return;
  if (mode_ == ShareMode::HostPtr) {
    glFinish();
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
  } else {
    glGetNamedBufferSubData(gl_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
    glCheck(("downloading from " + label_).c_str());
  }
}

}  // namespace ml
