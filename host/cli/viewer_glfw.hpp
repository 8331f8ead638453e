#pragma once
// The GLFW side of the viewer's input: callbacks on the window that push every key, mouse button,
// cursor motion and wheel event into an EventQueue (cli/viewer_controls.hpp) as it comes, so none
// is lost however slow the frame. glfwPollEvents() runs them on the calling thread.
#include <functional>

#include "cli/viewer_controls.hpp"

struct GLFWwindow;

namespace splatcl::cli::viewer {

class GlfwInput {
 public:
  // Installs the callbacks on `window` (its user pointer becomes this object). `forward`, when set,
  // gets every event's raw GLFW callback first (the panel's ImGui backend), and `captured` says
  // whether the panel holds the keyboard (argument true) or the mouse (false) at that moment.
  struct Hooks {
    std::function<void(GLFWwindow*, int key, int scancode, int action, int mods)> key;
    std::function<void(GLFWwindow*, unsigned codepoint)> character;
    std::function<void(GLFWwindow*, int button, int action, int mods)> button;
    std::function<void(GLFWwindow*, double x, double y)> cursor;
    std::function<void(GLFWwindow*, double dx, double dy)> scroll;
    std::function<void(GLFWwindow*, int entered)> enter;
    std::function<void(GLFWwindow*, int focused)> focus;
    std::function<bool(bool keyboard)> captured;
  };
  explicit GlfwInput(GLFWwindow* window, Hooks hooks = {});
  ~GlfwInput();  // removes the callbacks
  GlfwInput(const GlfwInput&) = delete;
  GlfwInput& operator=(const GlfwInput&) = delete;

  EventQueue& queue() { return queue_; }
  GLFWwindow* window() const { return window_; }
  // glfwPollEvents, its events stamped with the time the poll began: GLFW gives events no time of
  // their own, and stamped as each callback ran, a press and release delivered by one poll were
  // microseconds apart, so a tap moved by microseconds instead of Controls::kTapSeconds.
  void poll();

  // The callbacks themselves (installed on the window; public for the tests, which call them as
  // GLFW would: glfw has no way to inject events into a real window).
  static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void on_char(GLFWwindow* window, unsigned codepoint);
  static void on_button(GLFWwindow* window, int button, int action, int mods);
  static void on_cursor(GLFWwindow* window, double x, double y);
  static void on_scroll(GLFWwindow* window, double dx, double dy);
  static void on_enter(GLFWwindow* window, int entered);
  static void on_focus(GLFWwindow* window, int focused);

 private:
  GLFWwindow* window_;
  Hooks hooks_;
  EventQueue queue_;
  // The cursor as of the events polled so far: a click's position. glfwGetCursorPos asks the X
  // server for the pointer now, which may have moved on since the click.
  double cursor_x_ = 0, cursor_y_ = 0;
  bool have_cursor_ = false;
  double poll_time_ = -1;  // the last poll's start; before the first, each event's own time
  bool captured(bool keyboard) const { return hooks_.captured && hooks_.captured(keyboard); }
  // Stamps the event with the time and the panel's capture, and queues it.
  static void push(GLFWwindow* window, Event event, bool keyboard);
};

}  // namespace splatcl::cli::viewer
