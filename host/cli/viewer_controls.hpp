#pragma once
// The viewer's input logic without a window: input events in (keys, mouse buttons, cursor motion,
// wheel, each with the time it came), camera, selection and mode changes out. `splatcl view` feeds
// it from GLFW callbacks (cli/viewer_glfw.hpp) once per frame; the tests feed it directly.
//
// Every event is applied once, in order, however many arrive within one frame: ten taps of C are
// ten shading steps. Held keys (object moves and rotations) move by the time they were down within
// the frame, from their press and release times, so a tap shorter than a frame still moves.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.hpp"
#include "present/presenter.hpp"
#include "core/scene.hpp"
#include "core/mesh.hpp"

namespace splatcl::cli::viewer {

// Key, button, action and modifier codes: GLFW's values (cli/viewer_glfw.cpp checks them), so the
// adapter passes GLFW's codes through unchanged.
namespace key {
inline constexpr int Space = 32, Apostrophe = 39, Minus = 45, Equal = 61, Num0 = 48, Num1 = 49, Num8 = 56;
inline constexpr int A = 65, B = 66, C = 67, E = 69, F = 70, G = 71, H = 72, L = 76, M = 77, O = 79, P = 80, Q = 81, R = 82,
                     S = 83;
inline constexpr int Escape = 256, Tab = 258, Right = 262, Left = 263, Down = 264, Up = 265, PageUp = 266, PageDown = 267;
inline constexpr int F1 = 290, KeypadSubtract = 333, KeypadAdd = 334;
}  // namespace key
namespace button {
inline constexpr int Left = 0, Right = 1, Middle = 2;
}
namespace mod {
inline constexpr int Shift = 1, Control = 2, Alt = 4;
}
enum class Action : int { Release = 0, Press = 1, Repeat = 2 };

struct Event {
  enum class Type { Key, Button, Cursor, Scroll };
  Type type = Type::Key;
  double time = 0;  // seconds, on the clock of apply()'s `now`
  int code = 0;     // key or button
  Action action = Action::Press;
  int mods = 0;
  double x = 0, y = 0;  // Cursor and Button: cursor position in window coordinates (origin top left); Scroll: offsets
  // The panel had the keyboard (key events) or the mouse (the others) when the event came: it is
  // the panel's, and the controls ignore it (a release still ends a drag).
  bool captured = false;

  static Event key_event(int code, Action action, double time, int mods = 0);
  static Event button_event(int code, Action action, double x, double y, double time, int mods = 0);
  static Event cursor(double x, double y, double time);
  static Event scroll(double dx, double dy, double time);
};

// Events in arrival order; take() hands them over and empties the queue.
class EventQueue {
 public:
  void push(const Event& event) { events_.push_back(event); }
  std::vector<Event> take();
  std::size_t size() const { return events_.size(); }

 private:
  std::vector<Event> events_;
};

// The camera as an orbit about a target point: eye = target + distance · (cos p sin y, sin p, cos p cos y).
struct Orbit {
  float yaw = 0, pitch = 0.5f, distance = 8;
  glm::vec3 target{0};
  static Orbit from_camera(const Camera& camera);
  glm::vec3 eye() const;
  glm::vec3 forward() const;  // unit, eye → target
  glm::vec3 right() const;    // unit, horizontal
  glm::vec3 up() const;       // unit, the view's up (right × forward)
};

struct Bounds {
  glm::vec3 min{1e30f}, max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void add(const glm::vec3& p) { min = glm::min(min, p), max = glm::max(max, p); }
};

// What the viewer shows, besides the scene's own quality settings.
struct ViewState {
  present::DebugView debug_view = present::DebugView::Final;
  bool ambient_occlusion = true, pixel_ao = false;
  bool floor_pixels = true;  // the floor's AO and key-light shadows per pixel (Presenter::floor_per_pixel)
  bool paused = false, panel = true, quit = false;
  std::size_t selected = 0;        // object index (when the scene has objects)
  unsigned screenshots = 0;        // screenshots asked for and not yet taken (P)
  std::string message;             // the last pick's or action's result, for the panel
};

// The sequence a key steps through (shading, mode, shadows): the next value, or the previous one.
std::string step(const std::string& value, const std::vector<std::string>& values, bool backwards = false);

class Controls {
 public:
  // Works on `scene` (camera, objects, quality), which must outlive it. The scene's camera at this
  // point is the one R returns to, its objects' placements the ones Shift+R returns to.
  Controls(splatcl::Scene& scene, const ViewState& state = {});

  // Each object's mesh (model space), in scene order, for picking and fit-to-scene; objects
  // without one are neither picked nor framed (the floor frames an empty scene).
  void set_meshes(std::vector<const Mesh*> meshes) { meshes_ = std::move(meshes); }

  // Applies the events in order, then the held keys' motion up to `now` (seconds, the events'
  // clock), and writes the camera into the scene. `window` is the cursor coordinates' size (the
  // framebuffer may be larger: HiDPI), `time` the scene time of the frame (objects' placements).
  void apply(const std::vector<Event>& events, double now, glm::ivec2 window, float time);

  // The camera operations of the mouse and keys, also for the panel's buttons.
  void orbit_by(float dx, float dy);               // window pixels of drag
  void pan_by(float dx, float dy, int window_height);  // window pixels: the point under the cursor follows it
  void zoom(float steps);                          // wheel steps: > 0 closer, distance × 0.85 per step
  // The scene's bounds in view (their bounding sphere inside both fields of view at the last
  // window's aspect), the view direction kept.
  void fit(float time);
  void reset_camera();
  void reset_objects();
  // The object under the cursor at window position (x, y) (a ray cast against the meshes at
  // `time`), or none.
  std::optional<std::size_t> pick(double x, double y, glm::ivec2 window, float time) const;
  // Moves the selected object along the view's right (dx) and forward on the floor (dz) and up (dy),
  // in world units; an orbiting object stops where it is.
  void move_selected(float dx, float dy, float dz, float time);

  // World bounds of the objects' meshes at `time` (the floor square when there are none).
  Bounds scene_bounds(float time) const;

  // The values L and B switch on: the scene's LOD threshold and Blinn-Phong strength, or 1 pixel and 0.5;
  // and S's (and the panel's) silhouette resolve: the scene's depth jump, or quality.antialias's default.
  float lod_on() const { return lod_on_; }
  float specular_on() const { return specular_on_; }
  float antialias_on() const { return antialias_on_; }
  const Orbit& orbit() const { return orbit_; }
  Orbit& orbit() { return orbit_; }
  ViewState& state() { return state_; }
  const ViewState& state() const { return state_; }
  splatcl::Scene& scene() { return scene_; }
  // The camera of the current orbit (its own up; the scene's field of view and planes).
  Camera camera() const;

  // Held-key speeds: object moves in world units per second per unit of camera distance, and turns.
  static constexpr float kMoveSpeed = 0.25f, kTurnDegrees = 90.0f;
  // GLFW gives events no time of their own: they carry the time they were polled, once a frame, so
  // a tap whose press and release arrive in one poll (same time) counts as held this long, or the
  // frame if shorter (a 30 ms tap at 270 ms frames moved nothing until then, a helper's audit).
  static constexpr double kTapSeconds = 0.05;
  static constexpr double kClickPixels = 4;  // a press and release closer than this is a click (pick)

 private:
  splatcl::Scene& scene_;
  ViewState state_;
  Orbit orbit_, home_;
  std::vector<splatcl::ObjectSpec> initial_objects_;
  std::vector<const Mesh*> meshes_;
  float lod_on_, specular_on_, antialias_on_;
  float aspect_ = 1;  // of the last apply()'s window
  // Held keys: since when each is down (negative: up), and the time of the last apply().
  std::vector<double> down_since_;
  double frame_start_ = -1e300;
  // Mouse: position, buttons down, the press position of the left button and whether it dragged.
  double cursor_x_ = 0, cursor_y_ = 0;
  bool have_cursor_ = false;
  bool left_ = false, right_ = false, middle_ = false, shift_drag_ = false, dragged_ = false;
  double press_x_ = 0, press_y_ = 0;
  void on_key(const Event& e, float time);
  void on_button(const Event& e, glm::ivec2 window, float time);
  void on_cursor(const Event& e, glm::ivec2 window);
  void write_camera();
};

}  // namespace splatcl::cli::viewer
