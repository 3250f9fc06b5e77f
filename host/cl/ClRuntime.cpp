#include "host/cl/ClRuntime.hpp"

#include <CL/cl_gl.h>

#include <cstdlib>
#include <sstream>

#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

#ifndef CL_PLATFORM_NOT_FOUND_KHR
#define CL_PLATFORM_NOT_FOUND_KHR -1001
#endif
#ifndef CL_EGL_DISPLAY_KHR
#define CL_EGL_DISPLAY_KHR 0x2009
#endif
#ifndef CL_GLX_DISPLAY_KHR
#define CL_GLX_DISPLAY_KHR 0x200A
#endif

namespace ml {

namespace {
constexpr const char* kNoPlatformHelp =
    "no OpenCL platform found: install an OpenCL driver (CPU: `apt-get install pocl-opencl-icd`; "
    "GPU: your vendor's OpenCL ICD)";

template <typename T, cl_int Name, typename Obj>
T query(const Obj& obj) {
  T value{};
  obj.getInfo(Name, &value);
  return value;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ' || s.back() == '\n')) s.pop_back();
  return s;
}

}  // namespace

DeviceInfo queryDeviceInfo(const cl::Device& d) {
  DeviceInfo i;
  const cl::Platform p(d.getInfo<CL_DEVICE_PLATFORM>());
  i.platform_name = trimmed(p.getInfo<CL_PLATFORM_NAME>());
  i.platform_version = trimmed(p.getInfo<CL_PLATFORM_VERSION>());
  i.name = trimmed(d.getInfo<CL_DEVICE_NAME>());
  i.vendor = trimmed(d.getInfo<CL_DEVICE_VENDOR>());
  i.version = trimmed(d.getInfo<CL_DEVICE_VERSION>());
  i.driver_version = trimmed(d.getInfo<CL_DRIVER_VERSION>());
  i.c_version = trimmed(d.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
  i.extensions = d.getInfo<CL_DEVICE_EXTENSIONS>();
  i.type = d.getInfo<CL_DEVICE_TYPE>();
  i.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
  i.max_work_group_size = d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
  i.local_mem_size = d.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
  i.global_mem_size = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
  i.max_alloc_size = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
  return i;
}

bool DeviceInfo::hasExtension(std::string_view ext) const {
  std::istringstream ss(extensions);
  std::string word;
  while (ss >> word)
    if (word == ext) return true;
  return false;
}

DeviceChoice DeviceChoice::parse(std::string_view text, std::string_view origin) {
  DeviceChoice c;
  if (text.empty() || text == "default") return c;
  if (text == "gpu") {
    c.kind = Kind::Gpu;
    return c;
  }
  if (text == "cpu") {
    c.kind = Kind::Cpu;
    return c;
  }
  int value = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9' || value > 100000)
      throw UserError(std::string(origin) + ": expected gpu, cpu or a device index, got '" + std::string(text) + "'");
    value = value * 10 + (ch - '0');
  }
  c.kind = Kind::Index;
  c.index = value;
  return c;
}

DeviceChoice DeviceChoice::resolve(std::string_view flag_value) {
  if (!flag_value.empty()) return parse(flag_value, "--device");
  if (const char* env = std::getenv("MANYLIGHTS_DEVICE"); env && *env) return parse(env, "MANYLIGHTS_DEVICE");
  return {};
}

std::vector<DeviceListing> listDevices() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (e.err() == CL_PLATFORM_NOT_FOUND_KHR) throw UserError(kNoPlatformHelp);
    throw UserError("listing OpenCL platforms failed: " + describeClError(e));
  }
  if (platforms.empty()) throw UserError(kNoPlatformHelp);
  std::vector<DeviceListing> out;
  for (const auto& p : platforms) {
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // CL_DEVICE_NOT_FOUND on an empty platform is not an error for us
    }
    for (const auto& d : devices) out.push_back({static_cast<int>(out.size()), p, d, queryDeviceInfo(d)});
  }
  if (out.empty()) throw UserError(kNoPlatformHelp);
  return out;
}

std::unique_ptr<ClRuntime> ClRuntime::create(DeviceChoice choice, const GlShareHandles* gl) {
  auto devices = listDevices();
  const DeviceListing* pick = nullptr;
  switch (choice.kind) {
    case DeviceChoice::Kind::Index:
      if (choice.index < 0 || choice.index >= static_cast<int>(devices.size()))
        throw UserError("--device " + std::to_string(choice.index) + ": only " + std::to_string(devices.size()) +
                        " OpenCL device(s) present (see `manylights devices`)");
      pick = &devices[choice.index];
      break;
    case DeviceChoice::Kind::Gpu:
      for (const auto& d : devices)
        if (d.info.isGpu()) { pick = &d; break; }
      if (!pick) throw UserError("--device gpu: no OpenCL GPU device present (see `manylights devices`)");
      break;
    case DeviceChoice::Kind::Cpu:
      for (const auto& d : devices)
        if (d.info.isCpu()) { pick = &d; break; }
      if (!pick)
        throw UserError("--device cpu: no OpenCL CPU device present (install pocl-opencl-icd)");
      break;
    case DeviceChoice::Kind::Default:
      for (const auto& d : devices)
        if (d.info.isGpu()) { pick = &d; break; }
      if (!pick)
        for (const auto& d : devices)
          if (d.info.isCpu()) { pick = &d; break; }
      if (!pick) pick = &devices.front();
      break;
  }

  std::unique_ptr<ClRuntime> rt(new ClRuntime());
  rt->platform_ = pick->platform;
  rt->device_ = pick->device;
  rt->info_ = pick->info;
  try {
    bool shared = false;
    if (gl && gl->any() && rt->info_.hasExtension("cl_khr_gl_sharing")) {
      std::vector<cl_context_properties> props = {CL_CONTEXT_PLATFORM,
                                                  reinterpret_cast<cl_context_properties>(rt->platform_())};
      if (gl->egl_context) {
        props.insert(props.end(), {CL_GL_CONTEXT_KHR, reinterpret_cast<cl_context_properties>(gl->egl_context),
                                   CL_EGL_DISPLAY_KHR, reinterpret_cast<cl_context_properties>(gl->egl_display)});
      } else {
        props.insert(props.end(), {CL_GL_CONTEXT_KHR, reinterpret_cast<cl_context_properties>(gl->glx_context),
                                   CL_GLX_DISPLAY_KHR, reinterpret_cast<cl_context_properties>(gl->glx_display)});
      }
      props.push_back(0);
      cl_int err = CL_SUCCESS;
      cl::Context ctx(rt->device_, props.data(), nullptr, nullptr, &err);
      if (err == CL_SUCCESS) {
        rt->context_ = ctx;
        shared = true;
      }
    }
    if (!shared) rt->context_ = cl::Context(rt->device_);
    rt->gl_sharing_active_ = shared;
    rt->queue_ = cl::CommandQueue(rt->context_, rt->device_, CL_QUEUE_PROFILING_ENABLE);
  } catch (const cl::Error& e) {
    throw UserError("creating an OpenCL context on '" + rt->info_.name + "' failed: " + describeClError(e));
  }
  rt->programs_ = std::make_unique<ProgramBuilder>(rt->context_, rt->device_, rt->info_);
  return rt;
}

ClRuntime::~ClRuntime() = default;

std::string ClRuntime::describe() const {
  std::ostringstream ss;
  ss << "OpenCL: " << info_.platform_name << " | " << info_.name << " ("
     << (info_.isGpu() ? "GPU" : info_.isCpu() ? "CPU" : "other") << ", " << info_.compute_units
     << " compute units, " << info_.c_version << ")"
     << " | GL sharing: " << (gl_sharing_active_ ? "cl_khr_gl_sharing" : "fallback");
  return ss.str();
}

std::string clErrorName(cl_int code) {
  switch (code) {
#define ML_CASE(x) \
  case x:          \
    return #x " (" + std::to_string(code) + ")";
    ML_CASE(CL_SUCCESS)
    ML_CASE(CL_DEVICE_NOT_FOUND)
    ML_CASE(CL_DEVICE_NOT_AVAILABLE)
    ML_CASE(CL_COMPILER_NOT_AVAILABLE)
    ML_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    ML_CASE(CL_OUT_OF_RESOURCES)
    ML_CASE(CL_OUT_OF_HOST_MEMORY)
    ML_CASE(CL_PROFILING_INFO_NOT_AVAILABLE)
    ML_CASE(CL_MEM_COPY_OVERLAP)
    ML_CASE(CL_IMAGE_FORMAT_MISMATCH)
    ML_CASE(CL_IMAGE_FORMAT_NOT_SUPPORTED)
    ML_CASE(CL_BUILD_PROGRAM_FAILURE)
    ML_CASE(CL_MAP_FAILURE)
    ML_CASE(CL_MISALIGNED_SUB_BUFFER_OFFSET)
    ML_CASE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
    ML_CASE(CL_COMPILE_PROGRAM_FAILURE)
    ML_CASE(CL_LINKER_NOT_AVAILABLE)
    ML_CASE(CL_LINK_PROGRAM_FAILURE)
    ML_CASE(CL_INVALID_VALUE)
    ML_CASE(CL_INVALID_DEVICE_TYPE)
    ML_CASE(CL_INVALID_PLATFORM)
    ML_CASE(CL_INVALID_DEVICE)
    ML_CASE(CL_INVALID_CONTEXT)
    ML_CASE(CL_INVALID_QUEUE_PROPERTIES)
    ML_CASE(CL_INVALID_COMMAND_QUEUE)
    ML_CASE(CL_INVALID_HOST_PTR)
    ML_CASE(CL_INVALID_MEM_OBJECT)
    ML_CASE(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
    ML_CASE(CL_INVALID_IMAGE_SIZE)
    ML_CASE(CL_INVALID_SAMPLER)
    ML_CASE(CL_INVALID_BINARY)
    ML_CASE(CL_INVALID_BUILD_OPTIONS)
    ML_CASE(CL_INVALID_PROGRAM)
    ML_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
    ML_CASE(CL_INVALID_KERNEL_NAME)
    ML_CASE(CL_INVALID_KERNEL_DEFINITION)
    ML_CASE(CL_INVALID_KERNEL)
    ML_CASE(CL_INVALID_ARG_INDEX)
    ML_CASE(CL_INVALID_ARG_VALUE)
    ML_CASE(CL_INVALID_ARG_SIZE)
    ML_CASE(CL_INVALID_KERNEL_ARGS)
    ML_CASE(CL_INVALID_WORK_DIMENSION)
    ML_CASE(CL_INVALID_WORK_GROUP_SIZE)
    ML_CASE(CL_INVALID_WORK_ITEM_SIZE)
    ML_CASE(CL_INVALID_GLOBAL_OFFSET)
    ML_CASE(CL_INVALID_EVENT_WAIT_LIST)
    ML_CASE(CL_INVALID_EVENT)
    ML_CASE(CL_INVALID_OPERATION)
    ML_CASE(CL_INVALID_GL_OBJECT)
    ML_CASE(CL_INVALID_BUFFER_SIZE)
    ML_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
    ML_CASE(CL_INVALID_PROPERTY)
#undef ML_CASE
    case CL_PLATFORM_NOT_FOUND_KHR:
      return "CL_PLATFORM_NOT_FOUND_KHR (-1001)";
    default:
      return "OpenCL error " + std::to_string(code);
  }
}

std::string describeClError(const cl::Error& e) { return std::string(e.what()) + ": " + clErrorName(e.err()); }

}  // namespace ml
