#include "cli/viewer_glfw.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace splatcl::cli::viewer {

// The controls use GLFW's codes as they are.
static_assert(key::Space == GLFW_KEY_SPACE && key::Minus == GLFW_KEY_MINUS && key::Equal == GLFW_KEY_EQUAL);
static_assert(key::Num1 == GLFW_KEY_1 && key::Num8 == GLFW_KEY_8 && key::A == GLFW_KEY_A && key::R == GLFW_KEY_R);
static_assert(key::B == GLFW_KEY_B && key::C == GLFW_KEY_C && key::E == GLFW_KEY_E && key::F == GLFW_KEY_F && key::H == GLFW_KEY_H);
static_assert(key::L == GLFW_KEY_L && key::M == GLFW_KEY_M && key::O == GLFW_KEY_O && key::P == GLFW_KEY_P && key::Q == GLFW_KEY_Q);
static_assert(key::Escape == GLFW_KEY_ESCAPE && key::Tab == GLFW_KEY_TAB && key::Right == GLFW_KEY_RIGHT && key::Left == GLFW_KEY_LEFT);
static_assert(key::Down == GLFW_KEY_DOWN && key::Up == GLFW_KEY_UP && key::PageUp == GLFW_KEY_PAGE_UP && key::PageDown == GLFW_KEY_PAGE_DOWN);
static_assert(key::F1 == GLFW_KEY_F1 && key::KeypadAdd == GLFW_KEY_KP_ADD && key::KeypadSubtract == GLFW_KEY_KP_SUBTRACT);
static_assert(button::Left == GLFW_MOUSE_BUTTON_LEFT && button::Right == GLFW_MOUSE_BUTTON_RIGHT && button::Middle == GLFW_MOUSE_BUTTON_MIDDLE);
static_assert(mod::Shift == GLFW_MOD_SHIFT && mod::Control == GLFW_MOD_CONTROL && mod::Alt == GLFW_MOD_ALT);
static_assert(static_cast<int>(Action::Press) == GLFW_PRESS && static_cast<int>(Action::Release) == GLFW_RELEASE &&
              static_cast<int>(Action::Repeat) == GLFW_REPEAT);

namespace {
GlfwInput* self(GLFWwindow* window) { return static_cast<GlfwInput*>(glfwGetWindowUserPointer(window)); }
}  // namespace

GlfwInput::GlfwInput(GLFWwindow* window, Hooks hooks) : window_(window), hooks_(std::move(hooks)) {
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, on_key);
  glfwSetCharCallback(window_, on_char);
  glfwSetMouseButtonCallback(window_, on_button);
  glfwSetCursorPosCallback(window_, on_cursor);
  glfwSetScrollCallback(window_, on_scroll);
  glfwSetCursorEnterCallback(window_, on_enter);
  glfwSetWindowFocusCallback(window_, on_focus);
}

GlfwInput::~GlfwInput() {
  glfwSetKeyCallback(window_, nullptr);
  glfwSetCharCallback(window_, nullptr);
  glfwSetMouseButtonCallback(window_, nullptr);
  glfwSetCursorPosCallback(window_, nullptr);
  glfwSetScrollCallback(window_, nullptr);
  glfwSetCursorEnterCallback(window_, nullptr);
  glfwSetWindowFocusCallback(window_, nullptr);
  glfwSetWindowUserPointer(window_, nullptr);
}

void GlfwInput::poll() {
  poll_time_ = glfwGetTime();
  glfwPollEvents();
}

void GlfwInput::push(GLFWwindow* window, Event event, bool keyboard) {
  GlfwInput* in = self(window);
  event.time = in->poll_time_ >= 0 ? in->poll_time_ : glfwGetTime();
  event.captured = in->captured(keyboard);
  in->queue_.push(event);
}

void GlfwInput::on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
  GlfwInput* in = self(window);
  if (!in) return;
  if (in->hooks_.key) in->hooks_.key(window, key, scancode, action, mods);
  if (key != GLFW_KEY_UNKNOWN) push(window, Event::key_event(key, static_cast<Action>(action), 0, mods), true);
}

void GlfwInput::on_char(GLFWwindow* window, unsigned codepoint) {
  GlfwInput* in = self(window);
  if (in && in->hooks_.character) in->hooks_.character(window, codepoint);
}

void GlfwInput::on_button(GLFWwindow* window, int button, int action, int mods) {
  GlfwInput* in = self(window);
  if (!in) return;
  if (in->hooks_.button) in->hooks_.button(window, button, action, mods);
  double x = in->cursor_x_, y = in->cursor_y_;
  if (!in->have_cursor_) glfwGetCursorPos(window, &x, &y);
  push(window, Event::button_event(button, static_cast<Action>(action), x, y, 0, mods), false);
}

void GlfwInput::on_cursor(GLFWwindow* window, double x, double y) {
  if (GlfwInput* in = self(window)) {
    in->cursor_x_ = x, in->cursor_y_ = y, in->have_cursor_ = true;
    if (in->hooks_.cursor) in->hooks_.cursor(window, x, y);
    push(window, Event::cursor(x, y, 0), false);
  }
}

void GlfwInput::on_scroll(GLFWwindow* window, double dx, double dy) {
  if (GlfwInput* in = self(window)) {
    if (in->hooks_.scroll) in->hooks_.scroll(window, dx, dy);
    push(window, Event::scroll(dx, dy, 0), false);
  }
}

void GlfwInput::on_enter(GLFWwindow* window, int entered) {
  GlfwInput* in = self(window);
  if (in && in->hooks_.enter) in->hooks_.enter(window, entered);
}

void GlfwInput::on_focus(GLFWwindow* window, int focused) {
  GlfwInput* in = self(window);
  if (in && in->hooks_.focus) in->hooks_.focus(window, focused);
}

}  // namespace splatcl::cli::viewer
