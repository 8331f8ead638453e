// splatcl view: the presenter in a GLFW window. Input through GLFW callbacks into an event queue
// (cli/viewer_glfw.hpp) applied once per frame by the window-free controls (cli/viewer_controls.hpp):
// orbit, pan, zoom, fit and reset of the camera, picking and camera-relative moves of objects,
// modes and toggles; a Dear ImGui panel (cli/viewer_panel.hpp) with the timings and figures.
#include "present/gl.hpp"  // before GLFW, which must not pull in the legacy GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <signal.h>

#include <atomic>
#include <cmath>
#include <filesystem>

#include "cli/commands.hpp"
#include "cli/scene_figures.hpp"
#include "cli/scene_options.hpp"
#include "cli/viewer_controls.hpp"
#include "cli/viewer_glfw.hpp"
#include "cli/viewer_panel.hpp"
#include "io/image.hpp"
#include "io/in_flight.hpp"
#include "present/context.hpp"
#include "present/presenter.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {
namespace {

constexpr const char* kHelpKeys =
    "keys: left drag orbit, right/middle or Shift+left drag pan, wheel or +/- zoom, click picks an object | F fit scene, R reset camera,\n"
    "      Shift+R reset objects | Tab/Shift+Tab select object, arrows move it along the view (right, forward), PgUp/PgDn lift, Q/E rotate |\n"
    "      1-8 views (final, albedo, normals, ao, clusters, shadows, depth, footprints) | C/Shift+C shading clustered/tiled/brute |\n"
    "      M splats/points | L level of detail on/off | B Blinn-Phong highlights on/off | O ambient occlusion | A AO per splat/pixel |\n"
    "      G floor's AO and shadows per pixel/splat | S silhouette resolve on/off | H/Shift+H shadows splat/pixel/off |\n"
    "      F1 panel on/off | Space pause | P screenshot | Esc quit";

struct ViewOptions {
  SceneOptions scene;
  std::string size = "960x600", screenshot_dir = ".";
  double seconds = 0;  // > 0: quit after this many seconds (for scripted runs)
  bool no_panel = false, paused = false, screenshot_on_exit = false;
};

// SIGINT, SIGTERM and SIGHUP while the window runs: the loop ends after its frame and the run
// prints its summary and state as when the window closes (it died without a word), then exits
// with 128 + the signal, as it would have. A second signal, during a slow frame, ends it at once.
std::atomic<int> stop_signal{0};
void on_stop_signal(int signal) {
  if (stop_signal.exchange(signal) != 0) {
    ::signal(signal, SIG_DFL);
    ::raise(signal);
  }
}

class StopSignals {
 public:
  StopSignals() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(signal, &action, nullptr);
  }
  ~StopSignals() { remove_in_flight_files_on_termination(); }  // main's handlers again
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

int run_view(const ViewOptions& o) {
  auto [width, height] = present::parse_frame_size(o.size, "--size");
  if (!(std::isfinite(o.seconds) && o.seconds >= 0))
    throw Error(fmt::format("--seconds {} is not a duration in seconds (finite, not negative; 0 = until closed)", o.seconds));
  if (o.screenshot_on_exit && o.seconds <= 0) throw Error("--screenshot-on-exit needs --seconds (the time of the last frame)");
  if (!std::filesystem::is_directory(o.screenshot_dir))
    throw Error(fmt::format("--screenshots {}: {}", o.screenshot_dir,
                            std::filesystem::exists(o.screenshot_dir) ? "not a directory" : "no such directory"));
  const splatcl::Scene scene = o.scene.load();
  auto runtime = Runtime::create(o.scene.device.device);
  auto context = present::GlContext::window(width, height, "splatcl view");
  GLFWwindow* window = context->glfw_window();
  present::Presenter presenter = [&] {
    ProgressLine progress("view");
    return present::Presenter(scene, *runtime, width, height, o.scene.cache_dir(), asset_progress(progress, "view"));
  }();
  presenter.hdr_output = false;  // the window and screenshots show the tone-mapped image
  print_mesh_warnings(presenter);
  std::fprintf(stderr, "%s\n", kHelpKeys);

  splatcl::Scene& s = presenter.scene();
  viewer::ViewState initial;
  initial.debug_view = presenter.debug_view;
  initial.ambient_occlusion = presenter.ambient_occlusion;
  initial.pixel_ao = presenter.pixel_ao;
  initial.floor_pixels = presenter.floor_per_pixel;
  initial.panel = !o.no_panel;
  initial.paused = o.paused;
  viewer::Controls controls(s, initial);
  std::vector<const Mesh*> meshes;
  for (std::size_t i = 0; i < s.objects.size(); ++i) meshes.push_back(&presenter.assets(i).mesh);
  controls.set_meshes(meshes);
  const std::vector<ObjectFigures> figures = object_figures(presenter, s);

  viewer::Panel panel(window);
  viewer::GlfwInput input(window, panel.hooks());
  double time = s.time, last_clock = glfwGetTime(), panel_refreshed = -1;
  unsigned shots = 0;
  std::size_t frames = 0, panel_frames = 0;
  double frame_ms_total = 0, panel_ms_total = 0;
  present::FrameStats stats;
  const double started = glfwGetTime();
  const StopSignals stop_signals;
  while (!glfwWindowShouldClose(window) && stop_signal.load() == 0) {
    input.poll();
    const double now = glfwGetTime();
    // The last frame: the time is up (with --screenshot-on-exit it is drawn and shot first).
    const bool last = o.seconds > 0 && now - started > o.seconds;
    if (last && !o.screenshot_on_exit) break;
    int ww = 0, wh = 0;
    glfwGetWindowSize(window, &ww, &wh);
    std::vector<viewer::Event> events = input.queue().take();
    const bool input_came = !events.empty();
    controls.apply(events, now, {ww, wh}, static_cast<float>(time));
    viewer::ViewState& v = controls.state();
    if (v.quit) break;
    if (!v.paused) time += now - last_clock;
    last_clock = now;
    presenter.debug_view = v.debug_view;
    presenter.ambient_occlusion = v.ambient_occlusion;
    presenter.pixel_ao = v.pixel_ao;
    presenter.floor_per_pixel = v.floor_pixels;

    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window, &fw, &fh);
    if (fw > 0 && fh > 0) presenter.resize(fw, fh);
    stats = presenter.render(static_cast<float>(time));
    ++frames, frame_ms_total += stats.frame_ms;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitNamedFramebuffer(presenter.display_framebuffer(), 0, 0, 0, presenter.width(), presenter.height(), 0, 0,
                           presenter.width(), presenter.height(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
    // Screenshots read the presenter's image: never the panel.
    if (last) ++v.screenshots;
    for (; v.screenshots > 0; --v.screenshots) {
      const std::string path = fmt::format("{}/splatcl-view-{:03}.png", o.screenshot_dir, shots++);
      write_image_rgb(path, presenter.width(), presenter.height(), presenter.read_display_rgb());
      std::fprintf(stderr, "screenshot %s\n", path.c_str());
    }
    // The panel's ImGui frame runs when input came (its widgets stay live) and twice a second for
    // the readouts; the frames between composite its last image.
    const bool refresh = input_came || now - panel_refreshed >= 0.5;
    panel.draw(controls, stats, figures, static_cast<float>(time), fw, fh, refresh);
    if (panel.refreshed()) panel_refreshed = now;
    if (v.panel) ++panel_frames, panel_ms_total += panel.last_ms();
    if (last) {
      // The window as shown, panel included (the back buffer before the swap).
      const std::string path = fmt::format("{}/splatcl-view-window-{:03}.png", o.screenshot_dir, shots - 1);
      std::vector<float> rgb(static_cast<std::size_t>(fw) * static_cast<std::size_t>(fh) * 3);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      glReadBuffer(GL_BACK);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, fw, fh, GL_RGB, GL_FLOAT, rgb.data());
      write_image_rgb(path, fw, fh, rgb);
      std::fprintf(stderr, "screenshot %s\n", path.c_str());
    }
    glfwSwapBuffers(window);
    const std::string title =
        fmt::format("splatcl view | {:.1f} fps | {} {} {} | sel: {} | F1 panel", 1000.0 / stats.frame_ms, s.quality.shading,
                    s.quality.mode, present::to_string(presenter.debug_view),
                    s.objects.empty() ? "-" : s.objects[v.selected % s.objects.size()].name);
    glfwSetWindowTitle(window, title.c_str());
    if (last) break;
  }
  const double n = static_cast<double>(frames), np = static_cast<double>(panel_frames);
  fmt::print(stderr, "view: {} frames, {:.2f} ms per frame; panel {}\n", frames, frames ? frame_ms_total / n : 0.0,
             panel_frames ? fmt::format("on {} frames, {:.3f} ms per frame", panel_frames, panel_ms_total / np) : "hidden");
  // The state the input left (scripted runs and tests read it).
  const viewer::ViewState& v = controls.state();
  fmt::print(stderr, "view: state shading {}, mode {}, shadows {}, view {}, ao {}, pixel ao {}, lod {}, specular {}, selected {}, "
                     "distance {:.4f} (start {:.4f}), panel {}, paused {}, last pick: {}\n",
             s.quality.shading, s.quality.mode, s.quality.shadows, present::to_string(v.debug_view), v.ambient_occlusion ? "on" : "off",
             v.pixel_ao ? "on" : "off", s.quality.lod_error, s.quality.specular,
             s.objects.empty() ? "-" : s.objects[v.selected % s.objects.size()].name, controls.orbit().distance,
             viewer::Orbit::from_camera(scene.camera).distance, v.panel ? "on" : "off", v.paused ? "yes" : "no",
             v.message.empty() ? "-" : v.message);
  if (const int signal = stop_signal.load(); signal != 0) {
    fmt::print(stderr, "view: ended by signal {}\n", signal);
    return 128 + signal;
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
  sub->add_option("--seconds", o->seconds, "Close the window after this many seconds (scripted runs; 0 = when closed)");
  sub->add_flag("--no-panel", o->no_panel, "Start with the panel hidden (F1 shows it)");
  sub->add_flag("--paused", o->paused, "Start with the scene time stopped (Space runs it)");
  sub->add_flag("--screenshot-on-exit", o->screenshot_on_exit,
                "With --seconds: at the end, write the image (splatcl-view-NNN.png) and the window with the panel "
                "(splatcl-view-window-NNN.png) into the --screenshots directory");
  return [o] { return run_view(*o); };
}

}  // namespace splatcl::cli
