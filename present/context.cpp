#include "present/context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include "present/gl.hpp"
#include "runtime/error.hpp"

namespace splatcl::present {

std::unique_ptr<GlContext> GlContext::offscreen() {
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Error("EGL: eglGetPlatformDisplayEXT is missing (install libegl-mesa0)");
  EGLDisplay display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    throw Error(fmt::format("EGL: cannot initialise the surfaceless platform (error 0x{:x}; install libegl-mesa0)",
                            eglGetError()));
  if (!eglBindAPI(EGL_OPENGL_API)) throw Error("EGL: the OpenGL API is not available");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  // Configless: nothing is drawn to an EGL surface, only to the presenter's framebuffers.
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    const EGLint error = eglGetError();
    eglTerminate(display);
    throw Error(fmt::format("EGL: cannot create an OpenGL 4.5 core context (error 0x{:x})", error));
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    eglTerminate(display);
    throw Error("EGL: cannot make the surfaceless context current");
  }
  std::unique_ptr<GlContext> result(new GlContext);
  result->egl_display_ = display;
  result->egl_context_ = context;
  return result;
}

std::unique_ptr<GlContext> GlContext::window(int width, int height, const std::string& title) {
  if (!glfwInit()) throw Error("GLFW: cannot initialise (is there a display? try xvfb-run, or splatcl render)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw Error("GLFW: cannot open an OpenGL 4.5 core window");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);
  std::unique_ptr<GlContext> result(new GlContext);
  result->window_ = window;
  return result;
}

GlContext::~GlContext() {
  if (window_) {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  if (egl_display_) {
    eglMakeCurrent(egl_display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(egl_display_, egl_context_);
    eglTerminate(egl_display_);
  }
}

std::string GlContext::renderer() const {
  return fmt::format("{} | OpenGL {}", reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
                     reinterpret_cast<const char*>(glGetString(GL_VERSION)));
}

}  // namespace splatcl::present
