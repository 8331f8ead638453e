#pragma once
// The viewer's panel and overlay (Dear ImGui, GLFW and OpenGL 3 backends): fps and the per-stage
// table, every mode and toggle with its state, the splat scale k, depth ε and light count, the
// heat map's legend, the camera and each object's splat and CSM figures. Drawn into the window's
// default framebuffer after the presenter's image is blitted there, so the presenter's own
// framebuffers (screenshots, `splatcl render`) never contain it. F1 shows and hides it.
#include <memory>
#include <vector>

#include "cli/scene_figures.hpp"
#include "cli/viewer_controls.hpp"
#include "cli/viewer_glfw.hpp"
#include "present/presenter.hpp"

struct GLFWwindow;

namespace splatcl::cli::viewer {

class Panel {
 public:
  // Needs the window's GL context current. The backend's callbacks are not installed on the
  // window: GlfwInput forwards to them (hooks()).
  explicit Panel(GLFWwindow* window);
  ~Panel();
  Panel(const Panel&) = delete;
  Panel& operator=(const Panel&) = delete;

  // Forwarding of GLFW's callbacks to ImGui, and whether ImGui holds the keyboard or the mouse.
  GlfwInput::Hooks hooks() const;

  // Builds and draws one frame of the panel into the bound framebuffer (the window's). Widgets
  // change `controls` (its scene's quality, its view state) for the next frame. With the panel
  // hidden it draws nothing and takes no time.
  void draw(Controls& controls, const present::FrameStats& stats, const std::vector<ObjectFigures>& objects, float time);
  double last_ms() const { return last_ms_; }  // the last draw's CPU time

 private:
  GLFWwindow* window_;
  double last_ms_ = 0;
};

// The heat map's colours (the clusters view: lights per cluster over the frame's maximum): the
// shading's heat(t), t in [0, 1].
glm::vec3 heat_color(float t);

}  // namespace splatcl::cli::viewer
