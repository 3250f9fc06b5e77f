#pragma once
// The OpenCL device the program computes on: platform/device choice, context
// (optionally sharing objects with the current GL context), one in-order
// profiling queue, and the program builder with its on-disk binary cache.
//
// Device choice: `--device gpu|cpu|N|NAME` (N indexes the list printed by
// `manylights devices`; NAME is a case-insensitive part of one device's
// platform name, platform vendor or device name, e.g. `pocl`, `rusticl`,
// `llvmpipe`), else $MANYLIGHTS_DEVICE, else the first GPU, else the first CPU
// device (PoCL). Errors are UserErrors naming the flag or variable; a NAME
// that matches no device or several lists the devices.
#include <CL/opencl.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "host/util/PassTimings.hpp"

namespace ml {

class ProgramBuilder;

struct DeviceChoice {
  enum class Kind { Default, Gpu, Cpu, Index, Name };
  Kind kind = Kind::Default;
  int index = -1;
  std::string name;                 // Kind::Name: what to look for
  std::string origin = "--device";  // what errors name: the flag or MANYLIGHTS_DEVICE
  // Parses "gpu", "cpu", "default", a non-negative integer, or else a name
  // (text starting with a digit, '-' or '+' must be an index: "-1" and "1x"
  // are errors); `origin` names the flag or variable in the error message.
  static DeviceChoice parse(std::string_view text, std::string_view origin);
  // The --device value if non-empty, else $MANYLIGHTS_DEVICE, else Default.
  static DeviceChoice resolve(std::string_view flag_value);
};

// How buffers move between GL and CL (gl/SharedBuffer.hpp): interop
// (cl_khr_gl_sharing), hostptr (zero-copy host memory), copy (explicit copies).
enum class ShareMode { Interop, HostPtr, Copy };
std::string shareModeName(ShareMode m);

// Handles of the GL context the CL context should share with (cl_khr_gl_sharing),
// and what that context runs on, for matching it with the CL device. Handles
// all null: no sharing requested. Identity fields empty where unknown.
struct GlShareHandles {
  void* egl_display = nullptr;  // EGLDisplay
  void* egl_context = nullptr;  // EGLContext
  void* glx_display = nullptr;  // Display*  (GLFW on X11)
  void* glx_context = nullptr;  // GLXContext
  std::string renderer;         // GL_RENDERER
  std::string drm_node;         // EGL_EXT_device_drm(_render_node), e.g. /dev/dri/renderD128
  std::string pci_bus_id;       // "0000:01:00.0", from the DRM node's sysfs device link
  std::vector<unsigned char> device_uuid;  // 16 bytes, EGL_EXT_device_persistent_id
  bool any() const { return egl_context || glx_context; }
};

struct DeviceInfo {
  std::string platform_name;
  std::string platform_vendor;
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
  cl_device_fp_config single_fp_config = 0;
  bool host_unified_memory = false;  // CL_DEVICE_HOST_UNIFIED_MEMORY
  std::vector<unsigned char> uuid;   // cl_khr_device_uuid; empty if not offered
  std::string pci_bus_id;            // cl_khr_pci_bus_info as "0000:01:00.0"; empty if not offered
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

// Whether programs are built with -cl-fp32-correctly-rounded-divide-sqrt: when
// CL_DEVICE_SINGLE_FP_CONFIG offers CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT (else
// CL 1.2 allows 2.5-ulp division and 3-ulp sqrt, and tests comparing kernels
// with their C++ twins use a stated tolerance: tests/support/FpTolerance.hpp).
// Test-only hook: $MANYLIGHTS_TEST_INEXACT_DIVIDE=1 pretends it is not offered.
bool correctlyRoundedDivideSqrt(cl_device_fp_config single_fp_config);
// The options every program starts with: "-cl-std=CL1.2" and the fp32 option
// above where it applies (part of the binary-cache key with the rest).
std::string baseBuildOptions(cl_device_fp_config single_fp_config);
std::string baseBuildOptions(const cl::Device& device);

// Whether GL and CL run on the same device, and how that was decided: the
// sharing context itself, device UUIDs, PCI bus ids, or both being on the CPU
// (software GL beside CPU OpenCL). Unknown when nothing identifies them.
enum class SameDevice { Yes, No, Unknown };
struct DeviceMatch {
  SameDevice same = SameDevice::Unknown;
  std::string how;
  std::string text() const;  // "same device (device UUIDs match)", "unknown (...)"
};
bool isSoftwareRenderer(std::string_view gl_renderer);  // llvmpipe, softpipe, swrast
DeviceMatch matchDevices(const GlShareHandles& gl, const DeviceInfo& cl, bool sharing_active);
// GL in software beside a GPU CL device is almost surely a mistake (a missing
// GL driver): UserError naming the override $MANYLIGHTS_ALLOW_SOFTWARE_GL=1.
void refuseSoftwareGlBesideGpu(const GlShareHandles& gl, const DeviceInfo& cl);

// The share mode: $MANYLIGHTS_SHARE (`env`, empty if unset) when given, else
// interop when sharing is active, else hostptr where the zero-copy check
// passed, else copy. hostptr without zero copy falls back to copy. `note` is
// the one line saying why the mode is not what was asked for or expected
// (sharing refused: `sharing_failure`), empty otherwise.
struct ShareChoice {
  ShareMode mode = ShareMode::Copy;
  std::string note;
};
ShareChoice chooseShareMode(std::string_view env, bool sharing_active, bool zero_copy,
                            std::string_view sharing_failure);

// All devices of all platforms, in a stable order. Throws UserError naming the
// package to install when no platform is present.
std::vector<DeviceListing> listDevices();

// Every platform, with or without devices (`manylights devices`), in the order
// and with the indices of listDevices(). Throws like listDevices().
struct PlatformListing {
  cl::Platform platform;
  std::string name, vendor, version;
  std::vector<DeviceListing> devices;
};
std::vector<PlatformListing> listPlatforms();

// The index in `devices` of the one device whose platform name, platform
// vendor or device name contains `name` (ASCII case-insensitive). No match or
// several: UserError naming `origin` and listing every device.
std::size_t deviceIndexByName(const std::vector<DeviceInfo>& devices, std::string_view name, std::string_view origin);

class ClRuntime {
 public:
  // Creates the context. When `gl` is given, the default device is the GL
  // context's own (CL_CURRENT_DEVICE_FOR_GL_CONTEXT_KHR) where a platform can
  // tell, and the context tries to share with it (cl_khr_gl_sharing;
  // glSharingActive() is then true). A refused sharing context falls back to
  // a plain one and prints one line saying why; $MANYLIGHTS_SHARE=copy|hostptr
  // skips the attempt, =interop makes a refusal an error. Test-only hook:
  // $MANYLIGHTS_TEST_FAIL_SHARING=1 makes the attempt (on any device) fail.
  static std::unique_ptr<ClRuntime> create(DeviceChoice choice, const GlShareHandles* gl = nullptr);
  ~ClRuntime();

  const cl::Context& context() const { return context_; }
  const cl::Device& device() const { return device_; }
  const cl::Platform& platform() const { return platform_; }
  cl::CommandQueue& queue() { return queue_; }
  const DeviceInfo& info() const { return info_; }
  bool glSharingActive() const { return gl_sharing_active_; }
  ShareMode shareMode() const { return share_.mode; }
  // Why sharing was not used or the mode differs from the asked one; empty if it did not.
  const std::string& shareNote() const { return share_.note; }
  // Whether host-pointer buffers are zero-copy here: CL_DEVICE_HOST_UNIFIED_MEMORY
  // and mapping a CL_MEM_USE_HOST_PTR buffer yields the host pointer itself.
  bool zeroCopyHostPtr() const { return zero_copy_; }
  const DeviceMatch& deviceMatch() const { return match_; }
  // Where SharedBuffer hand-overs add their passes (share-acquire,
  // share-release, share-copy) while a frame is timed; null: not timed.
  PassTimings* shareTimings() const { return share_timings_; }
  void setShareTimings(PassTimings* sink) { share_timings_ = sink; }
  ProgramBuilder& programs() { return *programs_; }

  // One line: platform, device, compute units, OpenCL C version, share mode,
  // and (with a GL context) the GL renderer and whether it is the same device.
  std::string describe() const;

 private:
  ClRuntime() = default;
  cl::Platform platform_;
  cl::Device device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  DeviceInfo info_;
  bool gl_sharing_active_ = false;
  bool zero_copy_ = false;
  std::string failure_;  // why a sharing context was not made, if one was wanted
  ShareChoice share_;
  DeviceMatch match_;
  std::string gl_renderer_;  // empty without a GL context
  PassTimings* share_timings_ = nullptr;
  std::unique_ptr<ProgramBuilder> programs_;
  void createContext(const GlShareHandles* gl, std::string_view share_env);

};

// "CL_OUT_OF_RESOURCES (-5)" style name of an OpenCL error code.
std::string clErrorName(cl_int code);
// Turns a cl::Error into a readable message: "<function>: <error name>".
std::string describeClError(const cl::Error& e);

}  // namespace ml
