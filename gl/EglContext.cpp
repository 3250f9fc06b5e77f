// Headless GL 4.5 core through EGL, without any window system.
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "gl/GlCheck.hpp"
#include "gl/GlContext.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error " + std::to_string(e);
  }
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    const char* choice = std::getenv("MANYLIGHTS_EGL");
    const std::string want = choice ? choice : "";
    if (!want.empty() && want != "device" && want != "surfaceless")
      throw UserError("MANYLIGHTS_EGL: expected device or surfaceless (or unset), got '" + want + "'");
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool has_platform = client_ext && std::strstr(client_ext, "EGL_EXT_platform_base");
    if (want.empty() || want == "device") tryDevice(has_platform, client_ext, want == "device");
    if (display_ == EGL_NO_DISPLAY && (want.empty() || want == "surfaceless") && has_platform &&
        std::strstr(client_ext, "EGL_MESA_platform_surfaceless")) {
      display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (display_ != EGL_NO_DISPLAY && initialize()) platform_ = "EGL surfaceless";
      else display_ = EGL_NO_DISPLAY;
    }
    if (display_ == EGL_NO_DISPLAY && want.empty()) {
      display_ = eglGetDisplay(EGL_DEFAULT_DISPLAY);
      if (display_ != EGL_NO_DISPLAY && initialize()) platform_ = "EGL default display";
      else display_ = EGL_NO_DISPLAY;
    }
    if (display_ == EGL_NO_DISPLAY)
      throw UserError("no EGL display for headless OpenGL" +
                      std::string(want.empty() ? "" : " (MANYLIGHTS_EGL=" + want + ")") +
                      ": install libegl-mesa0 and libgl1-mesa-dri (Mesa) or a GPU driver with EGL");
    if (!eglBindAPI(EGL_OPENGL_API))
      throw UserError("EGL: desktop OpenGL API not available (" + eglErrorName(eglGetError()) + ")");

    EGLConfig config = EGL_NO_CONFIG_KHR;
    const char* dpy_ext = eglQueryString(display_, EGL_EXTENSIONS);
    if (!(dpy_ext && std::strstr(dpy_ext, "EGL_KHR_no_config_context"))) {
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(display_, attribs, &config, 1, &n) || n < 1)
        throw UserError("EGL: no OpenGL-capable config (" + eglErrorName(eglGetError()) + ")");
    }
    std::vector<EGLint> ctx_attribs = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
#ifndef NDEBUG
    ctx_attribs.insert(ctx_attribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
#endif
    ctx_attribs.push_back(EGL_NONE);
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, ctx_attribs.data());
    if (context_ == EGL_NO_CONTEXT)
      throw UserError("EGL: could not create an OpenGL 4.5 core context on " + platform_ + " (" +
                      eglErrorName(eglGetError()) + ")");
    makeCurrent();
    if (epoxy_gl_version() < 45)
      throw UserError("OpenGL 4.5 is required, the driver offers " + std::to_string(epoxy_gl_version() / 10) + "." +
                      std::to_string(epoxy_gl_version() % 10));
    installGlDebugOutput();
  }

  ~EglContext() override {
    if (display_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
      eglTerminate(display_);
    }
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw UserError("EGL: eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
  }

  std::string describe() const override {
    auto s = [](GLenum e) {
      const GLubyte* v = glGetString(e);
      return v ? std::string(reinterpret_cast<const char*>(v)) : std::string("?");
    };
    return "OpenGL: " + s(GL_VERSION) + " | " + s(GL_RENDERER) + " | " + platform_;
  }

  GlShareHandles shareHandles() const override {
    GlShareHandles h;
    h.egl_display = display_;
    h.egl_context = context_;
    const GLubyte* r = glGetString(GL_RENDERER);
    h.renderer = r ? reinterpret_cast<const char*>(r) : "";
    deviceIdentity(h);
    return h;
  }

 private:
  bool initialize() {
    EGLint major = 0, minor = 0;
    return eglInitialize(display_, &major, &minor) == EGL_TRUE;
  }

  void tryDevice(bool has_platform, const char* client_ext, bool required) {
    if (!has_platform || !client_ext || !std::strstr(client_ext, "EGL_EXT_device_enumeration")) return;
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!eglQueryDevicesEXT(16, devices, &count)) return;
    for (EGLint i = 0; i < count; ++i) {
      const char* dev_ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
      // Mesa lists its software rasterizer as a device too; unless asked for a
      // device explicitly, prefer the surfaceless platform for it.
      if (!required && dev_ext && std::strstr(dev_ext, "EGL_MESA_device_software")) continue;
      EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      if (d == EGL_NO_DISPLAY) continue;
      display_ = d;
      if (initialize()) {
        platform_ = "EGL device " + std::to_string(i);
        return;
      }
      display_ = EGL_NO_DISPLAY;
    }
  }

  // The EGL device behind the display (EGL_EXT_device_query), its DRM node
  // and PCI id (EGL_EXT_device_drm, sysfs) and UUID (EGL_EXT_device_persistent_id),
  // for matching with the CL device; fields stay empty where not offered.
  void deviceIdentity(GlShareHandles& h) const {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_ext || !std::strstr(client_ext, "EGL_EXT_device_query")) return;
    EGLAttrib attrib = 0;
    if (!eglQueryDisplayAttribEXT(display_, EGL_DEVICE_EXT, &attrib) || !attrib) return;
    auto device = reinterpret_cast<EGLDeviceEXT>(attrib);
    const char* dev_ext = eglQueryDeviceStringEXT(device, EGL_EXTENSIONS);
    if (!dev_ext) return;
    const char* node = nullptr;
    if (std::strstr(dev_ext, "EGL_EXT_device_drm_render_node")) node = eglQueryDeviceStringEXT(device, kEglDrmRenderNode);
    if (!node && std::strstr(dev_ext, "EGL_EXT_device_drm")) node = eglQueryDeviceStringEXT(device, EGL_DRM_DEVICE_FILE_EXT);
    if (node) {
      h.drm_node = node;
      h.pci_bus_id = pciBusIdOf(node);
    }
    using QueryBinary = EGLBoolean (*)(EGLDeviceEXT, EGLint, EGLint, void*, EGLint*);
    auto query_binary = reinterpret_cast<QueryBinary>(eglGetProcAddress("eglQueryDeviceBinaryEXT"));
    EGLint size = 0;
    std::vector<unsigned char> uuid(16);
    if (std::strstr(dev_ext, "EGL_EXT_device_persistent_id") && query_binary &&
        query_binary(device, kEglDeviceUuid, EGLint(uuid.size()), uuid.data(), &size) && size == 16)
      h.device_uuid = uuid;
  }

  // "/dev/dri/renderD128" -> "0000:01:00.0" through /sys/class/drm/<node>/device; empty if not PCI.
  static std::string pciBusIdOf(const std::string& node) {
    std::error_code ec;
    const auto name = std::filesystem::path(node).filename();
    const auto dev = std::filesystem::canonical(std::filesystem::path("/sys/class/drm") / name / "device", ec);
    if (ec) return {};
    const std::string id = dev.filename().string();  // PCI: dddd:bb:dd.f
    return id.size() == 12 && id[4] == ':' && id[7] == ':' && id[10] == '.' ? id : std::string();
  }

  static constexpr EGLint kEglDrmRenderNode = 0x3377;  // EGL_DRM_RENDER_NODE_FILE_EXT
  static constexpr EGLint kEglDeviceUuid = 0x335C;     // EGL_DEVICE_UUID_EXT

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string platform_;
};

}  // namespace

std::unique_ptr<GlContext> createHeadlessContext() { return std::make_unique<EglContext>(); }

}  // namespace ml
