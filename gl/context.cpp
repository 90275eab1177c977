#include "gl/context.h"

#include <array>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "util/error.h"
#include "util/names.h"

#if defined(__SANITIZE_ADDRESS__)
#define GANZFELD_LEAK_CHECKED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GANZFELD_LEAK_CHECKED 1
#endif
#endif
#ifdef GANZFELD_LEAK_CHECKED
#include <sanitizer/lsan_interface.h>
#endif

namespace ganzfeld::gl {

namespace {
constexpr std::array<util::EnumName<Platform>, 3> kPlatformNames{
    {{Platform::automatic, "auto"}, {Platform::device, "device"}, {Platform::surfaceless, "surfaceless"}}};
}  // namespace

const char* to_string(Platform platform) { return util::name_of(kPlatformNames, platform); }

Platform parse_platform(const std::string& text) { return util::parse_name(kPlatformNames, "EGL platform", text); }

#ifdef GANZFELD_LEAK_CHECKED
LeakCheckPause::LeakCheckPause() { __lsan_disable(); }
LeakCheckPause::~LeakCheckPause() { __lsan_enable(); }
#else
LeakCheckPause::LeakCheckPause() = default;
LeakCheckPause::~LeakCheckPause() = default;
#endif

Context::~Context() {
  if (display_ == EGL_NO_DISPLAY) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
  eglTerminate(display_);
}

namespace {

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(name);
  for (const char* at = std::strstr(list, name); at != nullptr; at = std::strstr(at + 1, name))
    if ((at == list || at[-1] == ' ') && (at[length] == ' ' || at[length] == '\0')) return true;
  return false;
}

std::string text(const char* s) { return s ? s : ""; }
std::string gl_string(GLenum name) { return text(reinterpret_cast<const char*>(glGetString(name))); }

/// The renderers that rasterize on the CPU (Mesa's llvmpipe and softpipe, SwiftShader).
bool software_renderer(const std::string& renderer) {
  for (const char* name : {"llvmpipe", "softpipe", "SwiftShader", "Software Rasterizer"})
    if (renderer.find(name) != std::string::npos) return true;
  return false;
}

/// Initializes `display` and makes a current context of `api` on it; "" or why not.
std::string start(EGLDisplay display, EGLDisplay& display_slot, EGLContext& context_slot, EGLSurface& surface_slot,
                  Api api) {
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    return "eglInitialize failed (EGL error " + std::to_string(eglGetError()) + ")";
  display_slot = display;  // terminated by ~Context from here on
  if (!eglBindAPI(api == Api::es30 ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) return "eglBindAPI failed";
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  const EGLint config_wanted[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                  api == Api::es30 ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(display, config_wanted, &config, 1, &configs)) configs = 0;
  if (configs == 0 && !has_extension(extensions, "EGL_KHR_no_config_context"))
    return "no pbuffer config for the API and no EGL_KHR_no_config_context";
  const EGLint core[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint gles[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
  context_slot = eglCreateContext(display, configs > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT,
                                  api == Api::es30 ? gles : core);
  if (context_slot == EGL_NO_CONTEXT)
    return "eglCreateContext failed (EGL error " + std::to_string(eglGetError()) + ")";
  if (!has_extension(extensions, "EGL_KHR_surfaceless_context")) {
    if (configs == 0) return "no EGL_KHR_surfaceless_context and no pbuffer config";
    const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    surface_slot = eglCreatePbufferSurface(display, config, size);
    if (surface_slot == EGL_NO_SURFACE) return "eglCreatePbufferSurface failed";
  }
  if (!eglMakeCurrent(display, surface_slot, surface_slot, context_slot))
    return "eglMakeCurrent failed (EGL error " + std::to_string(eglGetError()) + ")";
  return "";
}

}  // namespace

std::unique_ptr<Context> make_context(Api api, Platform platform, std::string& error) {
#ifdef GANZFELD_LEAK_CHECKED
  setenv("LP_NUM_THREADS", "0", 1);  // see LeakCheckPause
#endif
  error.clear();
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) {
    error = "no eglGetPlatformDisplayEXT (is libEGL from libglvnd or Mesa installed?)";
    return nullptr;
  }
  auto attempt = [&](EGLDisplay display, const std::string& platform_name,
                     const std::string& device) -> std::unique_ptr<Context> {
    std::unique_ptr<Context> context(new Context());
    const std::string why = start(display, context->display_, context->context_, context->surface_, api);
    if (!why.empty()) {
      error += (error.empty() ? "" : "; ") + platform_name + (device.empty() ? "" : " (" + device + ")") + ": " + why;
      return nullptr;
    }
    ContextInfo& info = context->info_;
    info.platform = platform_name;
    info.device = device;
    info.egl_vendor = text(eglQueryString(context->display_, EGL_VENDOR)) + ", EGL " +
                      text(eglQueryString(context->display_, EGL_VERSION));
    info.gl_vendor = gl_string(GL_VENDOR);
    info.gl_renderer = gl_string(GL_RENDERER);
    info.gl_version = gl_string(GL_VERSION);
    info.software = software_renderer(info.gl_renderer) || device.find("EGL_MESA_device_software") != std::string::npos;
    return context;
  };

  if (platform != Platform::surfaceless) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint count = 0;
    std::vector<EGLDeviceEXT> devices(16);
    if (has_extension(client, "EGL_EXT_platform_device") && query_devices && query_device_string &&
        query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count)) {
      devices.resize(static_cast<std::size_t>(count));
      std::vector<std::pair<EGLDeviceEXT, std::string>> hardware, software;
      for (EGLDeviceEXT device : devices) {
        const std::string extensions = text(query_device_string(device, EGL_EXTENSIONS));
        (has_extension(extensions.c_str(), "EGL_MESA_device_software") ? software : hardware)
            .push_back({device, extensions});
      }
      if (platform == Platform::device) hardware.insert(hardware.end(), software.begin(), software.end());
      for (const auto& [device, extensions] : hardware)
        if (auto context = attempt(get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr), "EGL device",
                                   extensions.empty() ? "a device" : extensions))
          return context;
      if (hardware.empty() && platform == Platform::device) error = "EGL device: no device";
    } else {
      error = "EGL device: no EGL_EXT_platform_device and EGL_EXT_device_enumeration";
    }
    if (platform == Platform::device) return nullptr;
  }
  if (!has_extension(client, "EGL_MESA_platform_surfaceless")) {
    error += std::string(error.empty() ? "" : "; ") + "EGL surfaceless: no EGL_MESA_platform_surfaceless";
    return nullptr;
  }
  auto context = attempt(get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                         "EGL surfaceless (Mesa)", "");
  if (!context) error += " (is Mesa's libegl-mesa0 installed?)";
  return context;
}

}  // namespace ganzfeld::gl
