#pragma once
// An OpenGL 4.5 core context: offscreen through EGL's surfaceless platform (no X server, Mesa
// llvmpipe), or a GLFW window. Rendering always goes to the presenter's own framebuffers; the
// window only receives a final blit.
#include <memory>
#include <string>

struct GLFWwindow;

namespace splatcl::present {

class GlContext {
 public:
  // Throws Error with the EGL error when no 4.5 core context can be made.
  static std::unique_ptr<GlContext> offscreen();
  // Throws Error when GLFW cannot open a window (no display).
  static std::unique_ptr<GlContext> window(int width, int height, const std::string& title);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  GLFWwindow* glfw_window() const { return window_; }
  std::string renderer() const;  // GL_RENDERER and GL_VERSION

 private:
  GlContext() = default;
  void* egl_display_ = nullptr;
  void* egl_context_ = nullptr;
  GLFWwindow* window_ = nullptr;
};

}  // namespace splatcl::present
