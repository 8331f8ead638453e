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

  // Draws the panel over the window's default framebuffer (width × height pixels). With `refresh`
  // (input came, or the readouts are due: view.cpp asks twice a second) it first runs an ImGui
  // frame, whose widgets change `controls` (its scene's quality, its view state), and renders it
  // into the panel's own layer; every frame it copies the panel window's rectangle of that layer
  // into the window (blends the whole layer while a tooltip is up). With the panel hidden it draws
  // nothing and takes no time.
  void draw(Controls& controls, const present::FrameStats& stats, const std::vector<ObjectFigures>& objects, float time, int width,
            int height, bool refresh);
  double last_ms() const { return last_ms_; }  // the last draw's time, its GL work finished included
  bool refreshed() const { return refreshed_; }  // the last draw ran an ImGui frame

 private:
  GLFWwindow* window_;
  double last_ms_ = 0;
  bool refreshed_ = false, have_layer_ = false;
  unsigned framebuffer_ = 0, texture_ = 0, program_ = 0, vertex_array_ = 0;
  int layer_width_ = 0, layer_height_ = 0;
  int rect_[4] = {0, 0, 0, 0};
  float window_min_[2] = {0, 0}, window_max_[2] = {0, 0};  // the panel window in ImGui's coordinates
  bool tooltip_ = false;                                  // a tooltip was up in the last ImGui frame  // the layer's drawn rectangle: x, y (bottom left), width, height
  // The cursor as of the polled events (the hooks' cursor callback). ImGui 1.86's backend reads the
  // pointer from the X server when its frame starts, after the frame's rendering: a slider dragged
  // and released, the pointer then moved on, was set to where the pointer went while ImGui still
  // saw the button down (a helper's audit: k 1.05 -> 3.0, the light count to 2^20).
  mutable double polled_cursor_[2] = {0, 0};
  mutable bool have_polled_cursor_ = false;
  void build(Controls& controls, const present::FrameStats& stats, const std::vector<ObjectFigures>& objects, float time);
  void resize_layer(int width, int height);
};

// The heat map's colours (the clusters view: lights per cluster over the frame's maximum): the
// shading's heat(t), t in [0, 1].
glm::vec3 heat_color(float t);

}  // namespace splatcl::cli::viewer
