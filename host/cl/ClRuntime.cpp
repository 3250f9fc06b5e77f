#include "host/cl/ClRuntime.hpp"

#include <CL/cl_ext.h>
#include <CL/cl_gl.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

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

// Device UUID and PCI bus id where the extensions offer them (raw queries:
// opencl.hpp has no traits for them), for matching with the GL device.
void queryIdentity(const cl::Device& d, DeviceInfo& i) {
  if (i.hasExtension("cl_khr_device_uuid")) {
    std::vector<unsigned char> uuid(CL_UUID_SIZE_KHR);
    if (clGetDeviceInfo(d(), CL_DEVICE_UUID_KHR, uuid.size(), uuid.data(), nullptr) == CL_SUCCESS) i.uuid = uuid;
  }
  if (i.hasExtension("cl_khr_pci_bus_info")) {
    cl_device_pci_bus_info_khr pci{};
    if (clGetDeviceInfo(d(), CL_DEVICE_PCI_BUS_INFO_KHR, sizeof pci, &pci, nullptr) == CL_SUCCESS) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%04x:%02x:%02x.%x", pci.pci_domain, pci.pci_bus, pci.pci_device,
                    pci.pci_function);
      i.pci_bus_id = buf;
    }
  }
}

}  // namespace

DeviceInfo queryDeviceInfo(const cl::Device& d) {
  DeviceInfo i;
  const cl::Platform p(d.getInfo<CL_DEVICE_PLATFORM>());
  i.platform_name = trimmed(p.getInfo<CL_PLATFORM_NAME>());
  i.platform_vendor = trimmed(p.getInfo<CL_PLATFORM_VENDOR>());
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
  i.single_fp_config = d.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>();
  i.host_unified_memory = d.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() == CL_TRUE;
  queryIdentity(d, i);
  return i;
}

bool correctlyRoundedDivideSqrt(cl_device_fp_config single_fp_config) {
  if (const char* hook = std::getenv("MANYLIGHTS_TEST_INEXACT_DIVIDE"); hook && std::string_view(hook) == "1")
    return false;
  return (single_fp_config & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
}

std::string baseBuildOptions(cl_device_fp_config single_fp_config) {
  std::string options = "-cl-std=CL1.2";
  if (correctlyRoundedDivideSqrt(single_fp_config)) options += " -cl-fp32-correctly-rounded-divide-sqrt";
  return options;
}

std::string baseBuildOptions(const cl::Device& device) {
  return baseBuildOptions(device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>());
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
  c.origin = std::string(origin);
  if (text.empty() || text == "default") return c;
  if (text == "gpu") {
    c.kind = Kind::Gpu;
    return c;
  }
  if (text == "cpu") {
    c.kind = Kind::Cpu;
    return c;
  }
  const char lead = text.front();
  if ((lead < '0' || lead > '9') && lead != '-' && lead != '+') {
    c.kind = Kind::Name;
    c.name = std::string(text);
    return c;
  }
  int value = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9' || value > 100000)
      throw UserError(std::string(origin) + ": expected gpu, cpu, a device index or a platform/device name, got '" +
                      std::string(text) + "'");
    value = value * 10 + (ch - '0');
  }
  c.kind = Kind::Index;
  c.index = value;
  return c;
}

namespace {

std::string lowered(std::string_view s) {
  std::string out(s);
  for (char& ch : out)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  return out;
}

bool nameMatches(const DeviceInfo& d, std::string_view wanted) {
  const std::string w = lowered(wanted);
  for (const std::string* field : {&d.platform_name, &d.platform_vendor, &d.name})
    if (lowered(*field).find(w) != std::string::npos) return true;
  return false;
}

}  // namespace

std::size_t deviceIndexByName(const std::vector<DeviceInfo>& devices, std::string_view name, std::string_view origin) {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (nameMatches(devices[i], name)) hits.push_back(i);
  if (hits.size() == 1) return hits.front();
  std::string list;
  for (std::size_t i = 0; i < devices.size(); ++i)
    list += (i ? "; " : "") + std::to_string(i) + ": " + devices[i].platform_name + " (" + devices[i].platform_vendor +
            ") / " + devices[i].name;
  const std::string what = hits.empty() ? "matches no OpenCL device" : "matches more than one OpenCL device";
  throw UserError(std::string(origin) + " '" + std::string(name) + "': " + what +
                  " (platform name, platform vendor or device name); the devices are: " + list);
}

DeviceChoice DeviceChoice::resolve(std::string_view flag_value) {
  if (!flag_value.empty()) return parse(flag_value, "--device");
  if (const char* env = std::getenv("MANYLIGHTS_DEVICE"); env && *env) return parse(env, "MANYLIGHTS_DEVICE");
  return {};
}

std::vector<PlatformListing> listPlatforms() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (e.err() == CL_PLATFORM_NOT_FOUND_KHR) throw UserError(kNoPlatformHelp);
    throw UserError("listing OpenCL platforms failed: " + describeClError(e));
  }
  if (platforms.empty()) throw UserError(kNoPlatformHelp);
  std::vector<PlatformListing> out;
  int index = 0;
  for (const auto& p : platforms) {
    PlatformListing& pl = out.emplace_back();
    pl.platform = p;
    pl.name = trimmed(p.getInfo<CL_PLATFORM_NAME>());
    pl.vendor = trimmed(p.getInfo<CL_PLATFORM_VENDOR>());
    pl.version = trimmed(p.getInfo<CL_PLATFORM_VERSION>());
    std::vector<cl::Device> devices;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // CL_DEVICE_NOT_FOUND on an empty platform is not an error for us
    }
    for (const auto& d : devices) pl.devices.push_back({index++, p, d, queryDeviceInfo(d)});
  }
  return out;
}

std::vector<DeviceListing> listDevices() {
  std::vector<DeviceListing> out;
  for (auto& p : listPlatforms())
    for (auto& d : p.devices) out.push_back(std::move(d));
  if (out.empty()) throw UserError(kNoPlatformHelp);
  return out;
}

namespace {

const DeviceListing* pickDevice(const std::vector<DeviceListing>& devices, DeviceChoice choice,
                                const DeviceListing* gl_device) {
  const auto first = [&](bool (DeviceInfo::*is)() const) -> const DeviceListing* {
    for (const auto& d : devices)
      if ((d.info.*is)()) return &d;
    return nullptr;
  };
  switch (choice.kind) {
    case DeviceChoice::Kind::Index:
      if (choice.index < 0 || choice.index >= static_cast<int>(devices.size()))
        throw UserError(choice.origin + " " + std::to_string(choice.index) + ": only " + std::to_string(devices.size()) +
                        " OpenCL device(s) present (see `manylights devices`)");
      return &devices[choice.index];
    case DeviceChoice::Kind::Gpu:
      if (gl_device && gl_device->info.isGpu()) return gl_device;
      if (auto* d = first(&DeviceInfo::isGpu)) return d;
      throw UserError(choice.origin + " gpu: no OpenCL GPU device present (see `manylights devices`)");
    case DeviceChoice::Kind::Cpu:
      if (auto* d = first(&DeviceInfo::isCpu)) return d;
      throw UserError(choice.origin + " cpu: no OpenCL CPU device present (install pocl-opencl-icd)");
    case DeviceChoice::Kind::Name: {
      std::vector<DeviceInfo> infos;
      for (const auto& d : devices) infos.push_back(d.info);
      return &devices[deviceIndexByName(infos, choice.name, choice.origin)];
    }
    case DeviceChoice::Kind::Default:
      break;
  }
  // The GL context's own device first: sharing needs it, and copies stay on one device.
  if (gl_device) return gl_device;
  if (auto* d = first(&DeviceInfo::isGpu)) return d;
  if (auto* d = first(&DeviceInfo::isCpu)) return d;
  return &devices.front();
}

std::vector<cl_context_properties> shareProperties(const cl::Platform& platform, const GlShareHandles& gl) {
  std::vector<cl_context_properties> props = {CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(platform())};
  if (gl.egl_context) {
    props.insert(props.end(), {CL_GL_CONTEXT_KHR, reinterpret_cast<cl_context_properties>(gl.egl_context),
                               CL_EGL_DISPLAY_KHR, reinterpret_cast<cl_context_properties>(gl.egl_display)});
  } else {
    props.insert(props.end(), {CL_GL_CONTEXT_KHR, reinterpret_cast<cl_context_properties>(gl.glx_context),
                               CL_GLX_DISPLAY_KHR, reinterpret_cast<cl_context_properties>(gl.glx_display)});
  }
  props.push_back(0);
  return props;
}

// The device the GL context runs on, as the first platform with
// cl_khr_gl_sharing reports it (clGetGLContextInfoKHR); null if none can tell.
const DeviceListing* glContextDevice(const std::vector<DeviceListing>& devices, const GlShareHandles& gl) {
  for (const auto& d : devices) {
    if (!d.info.hasExtension("cl_khr_gl_sharing")) continue;
    auto fn = reinterpret_cast<clGetGLContextInfoKHR_fn>(
        clGetExtensionFunctionAddressForPlatform(d.platform(), "clGetGLContextInfoKHR"));
    if (!fn) continue;
    const auto props = shareProperties(d.platform, gl);
    cl_device_id id = nullptr;
    if (fn(props.data(), CL_CURRENT_DEVICE_FOR_GL_CONTEXT_KHR, sizeof id, &id, nullptr) != CL_SUCCESS || !id) continue;
    for (const auto& e : devices)
      if (e.device() == id) return &e;
  }
  return nullptr;
}

bool envIs(const char* name, std::string_view value) {
  const char* v = std::getenv(name);
  return v && std::string_view(v) == value;
}

// CL_DEVICE_HOST_UNIFIED_MEMORY, and a CL_MEM_USE_HOST_PTR buffer maps to the
// host pointer itself (a discrete GPU may keep its own copy, defined on the
// host only after map/unmap: then hostptr mode would read stale bytes).
bool probeZeroCopy(const cl::Context& ctx, cl::CommandQueue& queue, const DeviceInfo& info) {
  if (!info.host_unified_memory) return false;
  constexpr std::size_t kBytes = 4096;
  void* host = std::aligned_alloc(kBytes, kBytes);
  if (!host) return false;
  bool same = false;
  try {
    cl::Buffer b(ctx, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, kBytes, host);
    void* mapped = queue.enqueueMapBuffer(b, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, kBytes);
    same = mapped == host;
    queue.enqueueUnmapMemObject(b, mapped);
    queue.finish();
  } catch (const cl::Error&) {
    same = false;
  }
  std::free(host);
  return same;
}

}  // namespace

std::unique_ptr<ClRuntime> ClRuntime::create(DeviceChoice choice, const GlShareHandles* gl) {
  const char* share_env_c = std::getenv("MANYLIGHTS_SHARE");
  const std::string share_env = share_env_c ? share_env_c : "";
  if (!share_env.empty() && share_env != "interop" && share_env != "hostptr" && share_env != "copy")
    throw UserError("MANYLIGHTS_SHARE: expected interop, hostptr or copy, got '" + share_env + "'");
  auto devices = listDevices();
  const bool with_gl = gl && gl->any();
  const DeviceListing* gl_device = with_gl ? glContextDevice(devices, *gl) : nullptr;
  const DeviceListing* pick = pickDevice(devices, choice, gl_device);

  std::unique_ptr<ClRuntime> rt(new ClRuntime());
  rt->platform_ = pick->platform;
  rt->device_ = pick->device;
  rt->info_ = pick->info;
  if (with_gl) {
    rt->gl_renderer_ = gl->renderer;
    refuseSoftwareGlBesideGpu(*gl, rt->info_);
  }
  std::string failure;
  if (with_gl && gl_device && gl_device != pick && share_env != "copy" && share_env != "hostptr")
    failure = "the GL context runs on '" + gl_device->info.name + "', not on the chosen OpenCL device";
  try {
    rt->createContext(with_gl && failure.empty() ? gl : nullptr, share_env);
  } catch (const cl::Error& e) {
    throw UserError("creating an OpenCL context on '" + rt->info_.name + "' failed: " + describeClError(e));
  }
  if (rt->failure_.empty()) rt->failure_ = failure;
  if (!rt->gl_sharing_active_) rt->zero_copy_ = probeZeroCopy(rt->context_, rt->queue_, rt->info_);
  rt->share_ = chooseShareMode(share_env, rt->gl_sharing_active_, rt->zero_copy_, rt->failure_);
  if (!rt->share_.note.empty()) std::fprintf(stderr, "manylights: note: %s\n", rt->share_.note.c_str());
  if (with_gl) rt->match_ = matchDevices(*gl, rt->info_, rt->gl_sharing_active_);
  rt->programs_ = std::make_unique<ProgramBuilder>(rt->context_, rt->device_, rt->info_);
  return rt;
}

// A sharing context where asked and possible, else (and on its refusal) a plain one.
void ClRuntime::createContext(const GlShareHandles* gl, std::string_view share_env) {
  const bool hook = envIs("MANYLIGHTS_TEST_FAIL_SHARING", "1");
  const bool attempt = gl && share_env != "copy" && share_env != "hostptr" &&
                       (info_.hasExtension("cl_khr_gl_sharing") || hook);
  if (attempt) {
    try {
      if (hook) throw cl::Error(CL_INVALID_OPERATION, "clCreateContext (MANYLIGHTS_TEST_FAIL_SHARING=1)");
      context_ = cl::Context(device_, shareProperties(platform_, *gl).data());
      gl_sharing_active_ = true;
    } catch (const cl::Error& e) {
      // Drivers differ in which GL contexts they share with: the run goes on without.
      failure_ = "the OpenCL driver refused a context sharing with GL (" + describeClError(e) + ")";
      if (share_env == "interop") throw UserError("MANYLIGHTS_SHARE=interop: " + failure_);
    }
  } else if (share_env == "interop") {
    throw UserError("MANYLIGHTS_SHARE=interop: " +
                    std::string(gl ? "the OpenCL device '" + info_.name + "' has no cl_khr_gl_sharing"
                                   : "no GL context to share with"));
  }
  if (!gl_sharing_active_) context_ = cl::Context(device_);
  queue_ = cl::CommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE);
}

ClRuntime::~ClRuntime() = default;

bool isSoftwareRenderer(std::string_view r) {
  return r.find("llvmpipe") != r.npos || r.find("softpipe") != r.npos || r.find("swrast") != r.npos;
}

std::string DeviceMatch::text() const {
  const char* s = same == SameDevice::Yes ? "same device" : same == SameDevice::No ? "different devices" : "unknown";
  return std::string(s) + " (" + how + ")";
}

DeviceMatch matchDevices(const GlShareHandles& gl, const DeviceInfo& cl, bool sharing_active) {
  const auto verdict = [](bool same, std::string how) {
    return DeviceMatch{same ? SameDevice::Yes : SameDevice::No, std::move(how)};
  };
  if (sharing_active) return {SameDevice::Yes, "cl_khr_gl_sharing context"};
  if (!gl.device_uuid.empty() && !cl.uuid.empty())
    return verdict(gl.device_uuid == cl.uuid, gl.device_uuid == cl.uuid ? "device UUIDs match" : "device UUIDs differ");
  if (!gl.pci_bus_id.empty() && !cl.pci_bus_id.empty())
    return verdict(gl.pci_bus_id == cl.pci_bus_id, "PCI " + gl.pci_bus_id + " vs " + cl.pci_bus_id);
  if (isSoftwareRenderer(gl.renderer))
    return verdict(cl.isCpu(), cl.isCpu() ? "software GL and OpenCL both on the CPU" : "software GL, OpenCL on a GPU");
  if (cl.isCpu()) return {SameDevice::No, "hardware GL, OpenCL on the CPU"};
  return {SameDevice::Unknown, "no device UUID or PCI id on one side"};
}

void refuseSoftwareGlBesideGpu(const GlShareHandles& gl, const DeviceInfo& cl) {
  if (!cl.isGpu() || !isSoftwareRenderer(gl.renderer) || envIs("MANYLIGHTS_ALLOW_SOFTWARE_GL", "1")) return;
  throw UserError("GL renders in software ('" + gl.renderer + "') beside the OpenCL GPU '" + cl.name +
                  "': install the GPU's GL/EGL driver, choose it with MANYLIGHTS_EGL=device, or set "
                  "MANYLIGHTS_ALLOW_SOFTWARE_GL=1 to run anyway");
}

std::string shareModeName(ShareMode m) {
  switch (m) {
    case ShareMode::Interop: return "interop";
    case ShareMode::HostPtr: return "hostptr";
    case ShareMode::Copy: return "copy";
  }
  return "?";
}

ShareChoice chooseShareMode(std::string_view env, bool sharing_active, bool zero_copy,
                            std::string_view sharing_failure) {
  ShareChoice c;
  if (sharing_active && (env.empty() || env == "interop")) {
    c.mode = ShareMode::Interop;
    return c;
  }
  c.mode = env != "copy" && zero_copy ? ShareMode::HostPtr : ShareMode::Copy;
  if (!sharing_failure.empty()) {
    c.note = std::string(sharing_failure) + ": using " + shareModeName(c.mode) + " mode";
  } else if (env != "copy" && !zero_copy) {
    c.note = std::string(env == "hostptr" ? "MANYLIGHTS_SHARE=hostptr: " : "") +
             "host-pointer buffers are not zero-copy on this device (no CL_DEVICE_HOST_UNIFIED_MEMORY, or "
             "mapping returned another pointer): using copy mode";
  }
  return c;
}

std::string ClRuntime::describe() const {
  std::ostringstream ss;
  ss << "OpenCL: " << info_.platform_name << " | " << info_.name << " ("
     << (info_.isGpu() ? "GPU" : info_.isCpu() ? "CPU" : "other") << ", " << info_.compute_units
     << " compute units, " << info_.c_version << ")"
     << " | share mode: " << shareModeName(share_.mode);
  if (!gl_renderer_.empty()) ss << " | GL on '" << gl_renderer_ << "': " << match_.text();
  return ss.str();
}

namespace {

// The codes of OpenCL 1.2 by name (and the ICD loader's "no platform").
#define ML_NAME(x) {x, #x}
constexpr std::pair<cl_int, const char*> kClErrorNames[] = {
    ML_NAME(CL_SUCCESS),
    ML_NAME(CL_DEVICE_NOT_FOUND), ML_NAME(CL_DEVICE_NOT_AVAILABLE),
    ML_NAME(CL_COMPILER_NOT_AVAILABLE), ML_NAME(CL_MEM_OBJECT_ALLOCATION_FAILURE),
    ML_NAME(CL_OUT_OF_RESOURCES), ML_NAME(CL_OUT_OF_HOST_MEMORY),
    ML_NAME(CL_PROFILING_INFO_NOT_AVAILABLE), ML_NAME(CL_MEM_COPY_OVERLAP),
    ML_NAME(CL_IMAGE_FORMAT_MISMATCH), ML_NAME(CL_IMAGE_FORMAT_NOT_SUPPORTED),
    ML_NAME(CL_BUILD_PROGRAM_FAILURE), ML_NAME(CL_MAP_FAILURE),
    ML_NAME(CL_MISALIGNED_SUB_BUFFER_OFFSET), ML_NAME(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST),
    ML_NAME(CL_COMPILE_PROGRAM_FAILURE), ML_NAME(CL_LINKER_NOT_AVAILABLE),
    ML_NAME(CL_LINK_PROGRAM_FAILURE), ML_NAME(CL_INVALID_VALUE),
    ML_NAME(CL_INVALID_DEVICE_TYPE), ML_NAME(CL_INVALID_PLATFORM),
    ML_NAME(CL_INVALID_DEVICE), ML_NAME(CL_INVALID_CONTEXT),
    ML_NAME(CL_INVALID_QUEUE_PROPERTIES), ML_NAME(CL_INVALID_COMMAND_QUEUE),
    ML_NAME(CL_INVALID_HOST_PTR), ML_NAME(CL_INVALID_MEM_OBJECT),
    ML_NAME(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR), ML_NAME(CL_INVALID_IMAGE_SIZE),
    ML_NAME(CL_INVALID_SAMPLER), ML_NAME(CL_INVALID_BINARY),
    ML_NAME(CL_INVALID_BUILD_OPTIONS), ML_NAME(CL_INVALID_PROGRAM),
    ML_NAME(CL_INVALID_PROGRAM_EXECUTABLE), ML_NAME(CL_INVALID_KERNEL_NAME),
    ML_NAME(CL_INVALID_KERNEL_DEFINITION), ML_NAME(CL_INVALID_KERNEL),
    ML_NAME(CL_INVALID_ARG_INDEX), ML_NAME(CL_INVALID_ARG_VALUE),
    ML_NAME(CL_INVALID_ARG_SIZE), ML_NAME(CL_INVALID_KERNEL_ARGS),
    ML_NAME(CL_INVALID_WORK_DIMENSION), ML_NAME(CL_INVALID_WORK_GROUP_SIZE),
    ML_NAME(CL_INVALID_WORK_ITEM_SIZE), ML_NAME(CL_INVALID_GLOBAL_OFFSET),
    ML_NAME(CL_INVALID_EVENT_WAIT_LIST), ML_NAME(CL_INVALID_EVENT),
    ML_NAME(CL_INVALID_OPERATION), ML_NAME(CL_INVALID_GL_OBJECT),
    ML_NAME(CL_INVALID_BUFFER_SIZE), ML_NAME(CL_INVALID_GLOBAL_WORK_SIZE),
    ML_NAME(CL_INVALID_PROPERTY),
    ML_NAME(CL_PLATFORM_NOT_FOUND_KHR),
};
#undef ML_NAME

}  // namespace

std::string clErrorName(cl_int code) {
  for (const auto& [value, name] : kClErrorNames)
    if (value == code) return std::string(name) + " (" + std::to_string(code) + ")";
  return "OpenCL error " + std::to_string(code);
}

std::string describeClError(const cl::Error& e) { return std::string(e.what()) + ": " + clErrorName(e.err()); }

}  // namespace ml
