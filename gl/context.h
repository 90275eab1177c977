// A headless OpenGL context through EGL, with no window system and no surface: the EGL device
// platform (EGL_EXT_platform_device: a GPU's driver, or Mesa's software device) or Mesa's
// surfaceless platform (EGL_MESA_platform_surfaceless: llvmpipe). The exported shaders are run
// in it by tests/gl_shader_test.cpp and measured by `ganzfeld bench shaders` (bench/shaders_bench.h).
//
// Platform order for Platform::automatic: every EGL device that is not a software one
// (EGL_MESA_device_software), then the surfaceless platform; Platform::device tries every device,
// software ones last. A context is made with a pbuffer-capable config where the display has one
// (NVIDIA's device displays), else without a config (EGL_KHR_no_config_context), and made current
// without a surface (EGL_KHR_surfaceless_context) or, where that is missing, on a 1 x 1 pbuffer;
// rendering goes to framebuffer objects either way.
#pragma once

#include <memory>
#include <string>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES
#endif
#include <GL/glcorearb.h>

namespace ganzfeld::gl {

enum class Api { core43, es30 };  ///< OpenGL 4.3 core profile, or OpenGL ES 3.0
enum class Platform { automatic, device, surfaceless };
const char* to_string(Platform platform);  ///< "auto", "device" or "surfaceless"
/// Accepts "auto", "device" and "surfaceless"; throws InputError otherwise.
Platform parse_platform(const std::string& text);

/// What the context runs on, as the implementation says.
struct ContextInfo {
  std::string platform;    ///< "EGL device" or "EGL surfaceless (Mesa)"
  std::string egl_vendor;  ///< EGL_VENDOR, and the EGL version
  std::string device;      ///< the device's extensions naming it (software, DRM node), "" for surfaceless
  std::string gl_vendor, gl_renderer, gl_version;  ///< GL_VENDOR, GL_RENDERER, GL_VERSION (the driver)
  bool software = false;                           ///< a CPU rasterizer (llvmpipe, softpipe, a software EGL device)
};

/// Under a leak checker (scripts/test --sanitize), llvmpipe's JIT-compiled shader code allocates
/// blocks that Mesa keeps past eglTerminate. Their stacks end in the JIT code, outside any module,
/// so no suppression can name them: leak checking is paused (for this thread; llvmpipe then
/// rasterizes on it too, LP_NUM_THREADS=0) while a context lives, and stays on for everything else.
struct LeakCheckPause {
  LeakCheckPause();
  ~LeakCheckPause();
  LeakCheckPause(const LeakCheckPause&) = delete;
  LeakCheckPause& operator=(const LeakCheckPause&) = delete;
};

/// A current context; destroying it releases the context, the surface and the display.
class Context {
 public:
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  const ContextInfo& info() const { return info_; }

 private:
  friend std::unique_ptr<Context> make_context(Api, Platform, std::string&);
  Context() = default;
  LeakCheckPause leak_check_pause_;  // destroyed last, after eglTerminate
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  ContextInfo info_;
};

/// A current context of `api` on `platform`, or nullptr and `error` saying why (every platform
/// tried, with the EGL error of each).
std::unique_ptr<Context> make_context(Api api, Platform platform, std::string& error);

}  // namespace ganzfeld::gl
