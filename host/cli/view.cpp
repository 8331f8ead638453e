// splatcl view: the presenter in a GLFW window. Orbit camera, occluder selection and movement,
// toggles for passes and modes, debug views, timings in the title bar, screenshots.
#include "present/gl.hpp"  // before GLFW, which must not pull in the legacy GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "cli/commands.hpp"
#include "cli/scene_options.hpp"
#include "io/image.hpp"
#include "present/context.hpp"
#include "present/presenter.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {
namespace {

constexpr const char* kHelpKeys =
    "keys: left drag orbit, wheel zoom | Tab select occluder, arrows move it in x/z, PgUp/PgDn lift, Q/E rotate |\n"
    "      1-8 views (final, albedo, normals, ao, clusters, shadows, depth, footprints) | C shading clustered/tiled/brute |\n"
    "      M splats/points | L level of detail on/off | B Blinn-Phong highlights on/off | O ambient occlusion | A AO per splat/pixel | H shadows splat/pixel/off | Space pause | P screenshot | Esc quit";

struct ViewOptions {
  SceneOptions scene;
  std::string size = "960x600", screenshot_dir = ".";
  double seconds = 0;  // > 0: quit after this many seconds (for scripted runs)
};

struct Orbit {
  float yaw = 0, pitch = 0.5f, distance = 8;
  glm::vec3 target{0};
};

template <class T>
T cycle(const T& value, std::initializer_list<T> values) {
  auto it = std::find(values.begin(), values.end(), value);
  return (it == values.end() || it + 1 == values.end()) ? *values.begin() : *(it + 1);
}

int run_view(const ViewOptions& o) {
  auto [width, height] = present::parse_frame_size(o.size, "--size");
  const present::Scene scene = o.scene.load();
  auto runtime = Runtime::create(o.scene.device.device);
  auto context = present::GlContext::window(width, height, "splatcl view");
  GLFWwindow* window = context->glfw_window();
  present::Presenter presenter(scene, *runtime, width, height, o.scene.cache_dir());
  presenter.hdr_output = false;  // the window and screenshots show the tone-mapped image
  std::fprintf(stderr, "%s\n", kHelpKeys);

  present::Scene& s = presenter.scene();
  Orbit orbit;
  {
    const glm::vec3 eye(s.camera.eye.x, s.camera.eye.y, s.camera.eye.z);
    orbit.target = {s.camera.target.x, s.camera.target.y, s.camera.target.z};
    const glm::vec3 d = eye - orbit.target;
    orbit.distance = glm::length(d);
    orbit.pitch = std::asin(d.y / orbit.distance);
    orbit.yaw = std::atan2(d.x, d.z);
  }
  // L toggles LOD between off and the scene's threshold (1 pixel when the scene has it off).
  const float lod_on = s.quality.lod_error > 0 ? s.quality.lod_error : 1.0f;
  const float specular_on = s.quality.specular > 0 ? s.quality.specular : 0.5f;  // B toggles Blinn-Phong
  std::size_t selected = 0;
  bool paused = false, screenshot = false;
  double time = s.time, last_clock = glfwGetTime(), drag_x = 0, drag_y = 0;
  bool dragging = false;
  unsigned shots = 0;
  const double started = glfwGetTime();
  while (!glfwWindowShouldClose(window)) {
    glfwPollEvents();
    const double now = glfwGetTime();
    if (!paused) time += now - last_clock;
    const float step = static_cast<float>(now - last_clock);
    last_clock = now;
    if (o.seconds > 0 && now - started > o.seconds) break;
    // Continuous input: occluder movement and camera drag.
    if (!s.objects.empty()) {
      present::ObjectSpec& obj = s.objects[selected % s.objects.size()];
      const float speed = 2.0f * step;
      if (glfwGetKey(window, GLFW_KEY_LEFT) == GLFW_PRESS) obj.position.x -= speed, obj.animation.orbit_radius = 0;
      if (glfwGetKey(window, GLFW_KEY_RIGHT) == GLFW_PRESS) obj.position.x += speed, obj.animation.orbit_radius = 0;
      if (glfwGetKey(window, GLFW_KEY_UP) == GLFW_PRESS) obj.position.z -= speed, obj.animation.orbit_radius = 0;
      if (glfwGetKey(window, GLFW_KEY_DOWN) == GLFW_PRESS) obj.position.z += speed, obj.animation.orbit_radius = 0;
      if (glfwGetKey(window, GLFW_KEY_PAGE_UP) == GLFW_PRESS) obj.position.y += speed;
      if (glfwGetKey(window, GLFW_KEY_PAGE_DOWN) == GLFW_PRESS) obj.position.y -= speed;
      if (glfwGetKey(window, GLFW_KEY_Q) == GLFW_PRESS) obj.rotation_degrees.y += 90 * step;
      if (glfwGetKey(window, GLFW_KEY_E) == GLFW_PRESS) obj.rotation_degrees.y -= 90 * step;
    }
    double mx = 0, my = 0;
    glfwGetCursorPos(window, &mx, &my);
    if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
      if (dragging) {
        orbit.yaw -= 0.01f * static_cast<float>(mx - drag_x);
        orbit.pitch = std::clamp(orbit.pitch + 0.01f * static_cast<float>(my - drag_y), -1.4f, 1.4f);
      }
      dragging = true;
    } else {
      dragging = false;
    }
    drag_x = mx, drag_y = my;
    const glm::vec3 eye = orbit.target + orbit.distance * glm::vec3(std::cos(orbit.pitch) * std::sin(orbit.yaw), std::sin(orbit.pitch),
                                                                    std::cos(orbit.pitch) * std::cos(orbit.yaw));
    s.camera.eye = {eye.x, eye.y, eye.z};

    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (fw > 0 && fh > 0) presenter.resize(fw, fh);
    const present::FrameStats stats = presenter.render(static_cast<float>(time));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitNamedFramebuffer(presenter.display_framebuffer(), 0, 0, 0, presenter.width(), presenter.height(), 0, 0,
                           presenter.width(), presenter.height(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (screenshot) {
      const std::string path = fmt::format("{}/splatcl-view-{:03}.png", o.screenshot_dir, shots++);
      write_image_rgb(path, presenter.width(), presenter.height(), presenter.read_display_rgb());
      std::fprintf(stderr, "screenshot %s\n", path.c_str());
      screenshot = false;
    }
    glfwSwapBuffers(window);
    std::string title = fmt::format("splatcl view | {:.1f} fps | {} {}{} {} | {} splats | sel: {} |", 1000.0 / stats.frame_ms,
                                    s.quality.shading, s.quality.mode,
                                    s.quality.lod_error > 0 ? fmt::format(" lod {}px", s.quality.lod_error) : "",
                                    present::to_string(presenter.debug_view), stats.splats,
                                    s.objects.empty() ? "-" : s.objects[selected % s.objects.size()].name);
    for (const auto& st : stats.stages) title += fmt::format(" {} {:.1f}", st.name, st.ms);
    glfwSetWindowTitle(window, title.c_str());

    // Key presses (edge-triggered through the user pointer's queue).
    static int previous[GLFW_KEY_LAST + 1] = {};
    const auto pressed = [&](int key) {
      const int state = glfwGetKey(window, key);
      const bool edge = state == GLFW_PRESS && previous[key] != GLFW_PRESS;
      previous[key] = state;
      return edge;
    };
    if (pressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(window, 1);
    if (pressed(GLFW_KEY_TAB)) ++selected;
    if (pressed(GLFW_KEY_SPACE)) paused = !paused;
    if (pressed(GLFW_KEY_P)) screenshot = true;
    if (pressed(GLFW_KEY_C)) s.quality.shading = cycle<std::string>(s.quality.shading, {"clustered", "tiled", "brute"});
    if (pressed(GLFW_KEY_M)) s.quality.mode = cycle<std::string>(s.quality.mode, {"splats", "points"});
    if (pressed(GLFW_KEY_H)) s.quality.shadows = cycle<std::string>(s.quality.shadows, {"splat", "pixel", "off"});
    if (pressed(GLFW_KEY_L)) s.quality.lod_error = s.quality.lod_error > 0 ? 0.0f : lod_on;
    if (pressed(GLFW_KEY_B)) s.quality.specular = s.quality.specular > 0 ? 0.0f : specular_on;
    if (pressed(GLFW_KEY_O)) presenter.ambient_occlusion = !presenter.ambient_occlusion;
    if (pressed(GLFW_KEY_A)) presenter.pixel_ao = !presenter.pixel_ao;
    for (int v = 0; v < 8; ++v)
      if (pressed(GLFW_KEY_1 + v)) presenter.debug_view = static_cast<present::DebugView>(v);
    if (pressed(GLFW_KEY_EQUAL)) orbit.distance *= 0.9f;
    if (pressed(GLFW_KEY_MINUS)) orbit.distance *= 1.1f;
  }
  return 0;
}

}  // namespace

Action register_view(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* sub = app.add_subcommand("view", "Show a presenter scene in a window (needs a display; see splatcl render for "
                                             "offscreen). Keys are listed on start");
  add_scene_options(*sub, o->scene);
  sub->add_option("--size", o->size, "Window size WIDTHxHEIGHT")->capture_default_str();
  sub->add_option("--screenshots", o->screenshot_dir, "Directory for screenshots (key P)")->capture_default_str();
  sub->add_option("--seconds", o->seconds, "Close the window after this many seconds (scripted runs)");
  return [o] { return run_view(*o); };
}

}  // namespace splatcl::cli
