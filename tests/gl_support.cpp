#include "tests/gl_support.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace ganzfeld::gl_test {

GlContext::~GlContext() {
  if (display != EGL_NO_DISPLAY) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
  }
}

std::unique_ptr<GlContext> make_context(bool es, std::string& error) {
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) {
    error = "no eglGetPlatformDisplayEXT";
    return nullptr;
  }
#ifdef GANZFELD_LEAK_CHECKED
  setenv("LP_NUM_THREADS", "0", 1);  // see LeakCheckPause
#endif
  auto gl = std::make_unique<GlContext>();
  gl->display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (gl->display == EGL_NO_DISPLAY || !eglInitialize(gl->display, &major, &minor)) {
    error = "eglInitialize failed on the surfaceless platform (is Mesa's libegl-mesa0 installed?)";
    gl->display = EGL_NO_DISPLAY;
    return nullptr;
  }
  if (!eglBindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) {
    error = "eglBindAPI failed";
    return nullptr;
  }
  const EGLint core[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint gles[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
  gl->context = eglCreateContext(gl->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, es ? gles : core);
  if (gl->context == EGL_NO_CONTEXT) {
    error = "eglCreateContext failed: EGL error " + std::to_string(eglGetError());
    return nullptr;
  }
  if (!eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context)) {
    error = "eglMakeCurrent (surfaceless) failed";
    return nullptr;
  }
  return gl;
}

GLuint compile(GLenum stage, const std::string& source, std::string& log) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char buffer[8192] = {};
    glGetShaderInfoLog(shader, sizeof buffer, nullptr, buffer);
    log = buffer;
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

const char* const kVertexCore = R"(#version 430 core
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
const char* const kVertexEs = R"(#version 300 es
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

/// A linked program of a vertex and a fragment shader (0 and `log` on failure).
GLuint link_program(const std::string& vertex, const std::string& fragment, std::string& log) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, log);
  if (vs == 0) return 0;
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, log);
  if (fs == 0) return 0;
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);  // flagged; freed with the program
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (linked) return program;
  log = "the program does not link";
  glDeleteProgram(program);
  return 0;
}

/// An RGBA32F framebuffer of width x height, bound; its names (framebuffer, renderbuffer).
std::array<GLuint, 2> float_framebuffer(int width, int height) {
  GLuint fbo = 0, color = 0;
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glGenRenderbuffers(1, &color);
  glBindRenderbuffer(GL_RENDERBUFFER, color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA32F, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
  glViewport(0, 0, width, height);
  return {fbo, color};
}

}  // namespace ganzfeld::gl_test
