// EGL + GL plumbing of the tests that run GLSL on Mesa's llvmpipe (tests/gl_shader_test.cpp,
// tests/gl_f_test.cpp): a surfaceless context, shader programs, a float framebuffer.
#pragma once

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <array>
#include <memory>
#include <string>

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

namespace ganzfeld::gl_test {

/// Under scripts/test --sanitize, llvmpipe's JIT-compiled shader code allocates blocks that Mesa
/// keeps past eglTerminate. Their stacks end in the JIT code, outside any module, so no
/// suppression can name them: leak checking is paused (for this thread; llvmpipe rasterizes on
/// it too, LP_NUM_THREADS=0) while a context lives, and stays on for everything else.
struct LeakCheckPause {
#ifdef GANZFELD_LEAK_CHECKED
  LeakCheckPause() { __lsan_disable(); }
  ~LeakCheckPause() { __lsan_enable(); }
#endif
};

struct GlContext {
  LeakCheckPause leak_check_pause;  // destroyed last, after eglTerminate
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ~GlContext();
};

/// A current GL 4.3 core (es = false) or GLSL ES 3.0 (es = true) context without any surface;
/// `error` says why not.
std::unique_ptr<GlContext> make_context(bool es, std::string& error);

/// A compiled shader of `stage` (0 and the info log in `log` on failure).
GLuint compile(GLenum stage, const std::string& source, std::string& log);

/// Full-screen triangle vertex shaders (gl_VertexID 0, 1, 2), GLSL 4.30 core and ES 3.00.
extern const char* const kVertexCore;
extern const char* const kVertexEs;

/// A linked program of a vertex and a fragment shader (0 and `log` on failure).
GLuint link_program(const std::string& vertex, const std::string& fragment, std::string& log);

/// An RGBA32F framebuffer of width x height, bound; its names (framebuffer, renderbuffer).
std::array<GLuint, 2> float_framebuffer(int width, int height);

}  // namespace ganzfeld::gl_test
