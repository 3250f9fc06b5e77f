#pragma once
// The OpenCL device the program computes on: platform/device choice, context
// (optionally sharing objects with the current GL context), one in-order
// profiling queue, and the program builder with its on-disk binary cache.
//
// Device choice: `--device gpu|cpu|N` (N indexes the list printed by
// `manylights devices`), else $MANYLIGHTS_DEVICE, else the first GPU, else the
// first CPU device (PoCL). Errors are UserErrors naming the flag or variable.
#include <CL/opencl.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace ml {

class ProgramBuilder;

struct DeviceChoice {
  enum class Kind { Default, Gpu, Cpu, Index };
  Kind kind = Kind::Default;
  int index = -1;
  // Parses "gpu", "cpu", "default" or a non-negative integer; `origin` names the
  // flag or variable in the error message.
  static DeviceChoice parse(std::string_view text, std::string_view origin);
  // The --device value if non-empty, else $MANYLIGHTS_DEVICE, else Default.
  static DeviceChoice resolve(std::string_view flag_value);
};

// Handles of the GL context the CL context should share with (cl_khr_gl_sharing).
// All null: no sharing requested.
struct GlShareHandles {
  void* egl_display = nullptr;  // EGLDisplay
  void* egl_context = nullptr;  // EGLContext
  void* glx_display = nullptr;  // Display*  (GLFW on X11)
  void* glx_context = nullptr;  // GLXContext
  bool any() const { return egl_context || glx_context; }
};

struct DeviceInfo {
  std::string platform_name;
  std::string platform_version;
  std::string name;
  std::string vendor;
  std::string version;
  std::string driver_version;
  std::string c_version;
  std::string extensions;
  cl_device_type type = 0;
  cl_uint compute_units = 0;
  size_t max_work_group_size = 0;
  cl_ulong local_mem_size = 0;
  cl_ulong global_mem_size = 0;
  cl_ulong max_alloc_size = 0;
  bool isCpu() const { return (type & CL_DEVICE_TYPE_CPU) != 0; }
  bool isGpu() const { return (type & CL_DEVICE_TYPE_GPU) != 0; }
  bool hasExtension(std::string_view ext) const;
};

struct DeviceListing {
  int index;
  cl::Platform platform;
  cl::Device device;
  DeviceInfo info;
};

// The device's (and its platform's) properties, strings trimmed of padding.
DeviceInfo queryDeviceInfo(const cl::Device& d);

// All devices of all platforms, in a stable order. Throws UserError naming the
// package to install when no platform is present.
std::vector<DeviceListing> listDevices();

class ClRuntime {
 public:
  // Creates the context. When `gl` is given and the device has
  // cl_khr_gl_sharing, the context shares with that GL context
  // (glSharingActive() is then true); otherwise a plain context.
  static std::unique_ptr<ClRuntime> create(DeviceChoice choice, const GlShareHandles* gl = nullptr);
  ~ClRuntime();

  const cl::Context& context() const { return context_; }
  const cl::Device& device() const { return device_; }
  const cl::Platform& platform() const { return platform_; }
  cl::CommandQueue& queue() { return queue_; }
  const DeviceInfo& info() const { return info_; }
  bool glSharingActive() const { return gl_sharing_active_; }
  ProgramBuilder& programs() { return *programs_; }

  // One line: platform, device, compute units, OpenCL C version, sharing mode.
  std::string describe() const;

 private:
  ClRuntime() = default;
  cl::Platform platform_;
  cl::Device device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  DeviceInfo info_;
  bool gl_sharing_active_ = false;
  std::unique_ptr<ProgramBuilder> programs_;
};

// "CL_OUT_OF_RESOURCES (-5)" style name of an OpenCL error code.
std::string clErrorName(cl_int code);
// Turns a cl::Error into a readable message: "<function>: <error name>".
std::string describeClError(const cl::Error& e);

}  // namespace ml
