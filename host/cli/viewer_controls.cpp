#include "cli/viewer_controls.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace splatcl::cli::viewer {
namespace {

// The held keys and what they do: move (right, up, forward) or turn about y.
struct HeldKey {
  int code;
  glm::vec3 move;
  float turn;
};
constexpr std::array<HeldKey, 8> kHeld = {{{key::Left, {-1, 0, 0}, 0},
                                           {key::Right, {1, 0, 0}, 0},
                                           {key::Up, {0, 0, 1}, 0},
                                           {key::Down, {0, 0, -1}, 0},
                                           {key::PageUp, {0, 1, 0}, 0},
                                           {key::PageDown, {0, -1, 0}, 0},
                                           {key::Q, {0, 0, 0}, 1},
                                           {key::E, {0, 0, 0}, -1}}};

int held_index(int code) {
  for (std::size_t i = 0; i < kHeld.size(); ++i)
    if (kHeld[i].code == code) return static_cast<int>(i);
  return -1;
}

glm::vec3 to_glm(Vec3 v) { return {v.x, v.y, v.z}; }

// Möller–Trumbore: the ray parameter of the hit, or a negative value.
float ray_triangle(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return -1;
  const float inv = 1.0f / det;
  const glm::vec3 s = o - a;
  const float u = glm::dot(s, p) * inv;
  if (u < 0 || u > 1) return -1;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(d, q) * inv;
  if (v < 0 || u + v > 1) return -1;
  return glm::dot(e2, q) * inv;
}

// The ray's entry parameter into the box, or +inf when it misses.
float ray_box(const glm::vec3& o, const glm::vec3& d, const Bounds& box) {
  float t0 = 0, t1 = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < box.min[k] || o[k] > box.max[k]) return std::numeric_limits<float>::infinity();
      continue;
    }
    float a = (box.min[k] - o[k]) / d[k], b = (box.max[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
    if (t0 > t1) return std::numeric_limits<float>::infinity();
  }
  return t0;
}

Bounds mesh_bounds(const Mesh& mesh) {
  Bounds b;
  for (const Vec3& v : mesh.vertices) b.add(to_glm(v));
  return b;
}

}  // namespace

Event Event::key_event(int code, Action action, double time, int mods) {
  Event e;
  e.type = Type::Key, e.code = code, e.action = action, e.time = time, e.mods = mods;
  return e;
}
Event Event::button_event(int code, Action action, double x, double y, double time, int mods) {
  Event e;
  e.type = Type::Button, e.code = code, e.action = action, e.x = x, e.y = y, e.time = time, e.mods = mods;
  return e;
}
Event Event::cursor(double x, double y, double time) {
  Event e;
  e.type = Type::Cursor, e.x = x, e.y = y, e.time = time;
  return e;
}
Event Event::scroll(double dx, double dy, double time) {
  Event e;
  e.type = Type::Scroll, e.x = dx, e.y = dy, e.time = time;
  return e;
}

std::vector<Event> EventQueue::take() {
  std::vector<Event> out;
  out.swap(events_);
  return out;
}

Orbit Orbit::from_camera(const Camera& camera) {
  Orbit o;
  const glm::vec3 eye = to_glm(camera.eye);
  o.target = to_glm(camera.target);
  const glm::vec3 d = eye - o.target;
  o.distance = std::max(glm::length(d), 1e-3f);
  o.pitch = std::clamp(std::asin(std::clamp(d.y / o.distance, -1.0f, 1.0f)), -1.4f, 1.4f);
  o.yaw = std::atan2(d.x, d.z);
  return o;
}

glm::vec3 Orbit::eye() const {
  return target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
}
glm::vec3 Orbit::forward() const { return glm::normalize(target - eye()); }
glm::vec3 Orbit::right() const { return {std::cos(yaw), 0.0f, -std::sin(yaw)}; }
glm::vec3 Orbit::up() const { return glm::cross(right(), forward()); }

std::string step(const std::string& value, const std::vector<std::string>& values, bool backwards) {
  const auto it = std::find(values.begin(), values.end(), value);
  if (it == values.end()) return values.front();
  const std::size_t i = static_cast<std::size_t>(it - values.begin()), n = values.size();
  return values[backwards ? (i + n - 1) % n : (i + 1) % n];
}

Controls::Controls(splatcl::Scene& scene, const ViewState& state)
    : scene_(scene),
      state_(state),
      orbit_(Orbit::from_camera(scene.camera)),
      home_(orbit_),
      initial_objects_(scene.objects),
      // L toggles LOD between off and the scene's threshold (1 pixel when the scene has it off), B Blinn-Phong.
      lod_on_(scene.quality.lod_error > 0 ? scene.quality.lod_error : 1.0f),
      specular_on_(scene.quality.specular > 0 ? scene.quality.specular : 0.5f),
      antialias_on_(scene.quality.antialias > 0 ? scene.quality.antialias : splatcl::Quality{}.antialias),
      down_since_(kHeld.size(), -1.0) {
  write_camera();
}

Camera Controls::camera() const {
  Camera c = scene_.camera;
  const glm::vec3 eye = orbit_.eye(), up = orbit_.up();
  c.eye = {eye.x, eye.y, eye.z};
  c.target = {orbit_.target.x, orbit_.target.y, orbit_.target.z};
  // The orbit's own up (its pitch stays within +-1.4 rad): a scene's up of -z for a top view rolled
  // the image as the orbit turned and became parallel to the view at pitch 0.
  c.up = {up.x, up.y, up.z};
  return c;
}

void Controls::write_camera() { scene_.camera = camera(); }

void Controls::orbit_by(float dx, float dy) {
  orbit_.yaw -= 0.01f * dx;
  orbit_.pitch = std::clamp(orbit_.pitch + 0.01f * dy, -1.4f, 1.4f);
  write_camera();
}

void Controls::pan_by(float dx, float dy, int window_height) {
  // One window pixel at the target's depth.
  const float pixel = 2.0f * orbit_.distance * std::tan(0.5f * scene_.camera.fov_y) / static_cast<float>(std::max(window_height, 1));
  orbit_.target += pixel * (-dx * orbit_.right() + dy * orbit_.up());
  write_camera();
}

void Controls::zoom(float steps) {
  const float lo = 2.0f * scene_.camera.near_plane, hi = 0.5f * scene_.camera.far_plane;
  orbit_.distance = std::clamp(orbit_.distance * std::pow(0.85f, steps), lo, std::max(lo, hi));
  write_camera();
}

Bounds Controls::scene_bounds(float time) const {
  Bounds all;
  for (std::size_t i = 0; i < scene_.objects.size() && i < meshes_.size(); ++i) {
    if (!meshes_[i] || meshes_[i]->vertices.empty()) continue;
    const Bounds local = mesh_bounds(*meshes_[i]);
    const glm::mat4 m = scene_.objects[i].placement(time);
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? local.max.x : local.min.x, (c & 2) ? local.max.y : local.min.y,
                             (c & 4) ? local.max.z : local.min.z);
      all.add(glm::vec3(m * glm::vec4(corner, 1.0f)));
    }
  }
  if (all.empty()) {
    const float h = 0.5f * (scene_.floor.enabled ? scene_.floor.size : 2.0f);
    all.add({-h, scene_.floor.y, -h});
    all.add({h, scene_.floor.y, h});
  }
  return all;
}

void Controls::fit(float time) {
  const Bounds b = scene_bounds(time);
  const glm::vec3 centre = 0.5f * (b.min + b.max);
  const float radius = std::max(0.5f * glm::length(b.max - b.min), 1e-3f);
  // The bounding sphere inside the narrower of the two fields of view.
  const float half_y = 0.5f * scene_.camera.fov_y, half = std::min(half_y, std::atan(std::tan(half_y) * aspect_));
  orbit_.target = centre;
  orbit_.distance = std::max(radius / std::sin(half), 2.0f * scene_.camera.near_plane);
  write_camera();
}

void Controls::reset_camera() {
  orbit_ = home_;
  write_camera();
}

void Controls::reset_objects() {
  if (scene_.objects.size() == initial_objects_.size()) scene_.objects = initial_objects_;
}

std::optional<std::size_t> Controls::pick(double x, double y, glm::ivec2 window, float time) const {
  if (window.x <= 0 || window.y <= 0) return std::nullopt;
  const Camera cam = camera();
  const glm::vec3 eye = orbit_.eye();
  const glm::mat4 view = glm::lookAt(eye, orbit_.target, to_glm(cam.up));
  const glm::mat4 proj = glm::perspective(cam.fov_y, static_cast<float>(window.x) / static_cast<float>(window.y), cam.near_plane,
                                          cam.far_plane);
  const glm::mat4 inverse = glm::inverse(proj * view);
  const float nx = static_cast<float>(2.0 * x / window.x - 1.0), ny = static_cast<float>(1.0 - 2.0 * y / window.y);
  const glm::vec4 far_point = inverse * glm::vec4(nx, ny, 1.0f, 1.0f);
  const glm::vec3 direction = glm::normalize(glm::vec3(far_point) / far_point.w - eye);

  std::optional<std::size_t> best;
  float best_t = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < scene_.objects.size() && i < meshes_.size(); ++i) {
    if (!meshes_[i]) continue;
    const Mesh& mesh = *meshes_[i];
    // The ray in model space: the same parameter t along it (the direction is not renormalised).
    const glm::mat4 to_model = glm::inverse(scene_.objects[i].placement(time));
    const glm::vec3 o = glm::vec3(to_model * glm::vec4(eye, 1.0f)), d = glm::vec3(to_model * glm::vec4(direction, 0.0f));
    if (ray_box(o, d, mesh_bounds(mesh)) >= best_t) continue;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const std::uint32_t first = mesh.face_offsets[f], last = mesh.face_offsets[f + 1];
      for (std::uint32_t k = first + 1; k + 1 < last; ++k) {  // a fan over the polygon
        const float t = ray_triangle(o, d, to_glm(mesh.vertices[mesh.corners[first]]), to_glm(mesh.vertices[mesh.corners[k]]),
                                     to_glm(mesh.vertices[mesh.corners[k + 1]]));
        if (t > 0 && t < best_t) best_t = t, best = i;
      }
    }
  }
  return best;
}

void Controls::move_selected(float dx, float dy, float dz, float time) {
  if (scene_.objects.empty()) return;
  splatcl::ObjectSpec& obj = scene_.objects[state_.selected % scene_.objects.size()];
  if (obj.animation.orbit_radius > 0 && (dx != 0 || dz != 0)) {
    // Stop the orbit where the object is now.
    obj.position = glm::vec3(obj.placement(time)[3]);
    obj.animation.orbit_radius = 0;
  }
  glm::vec3 forward = orbit_.forward();
  forward.y = 0;
  forward = glm::length(forward) > 1e-6f ? glm::normalize(forward) : glm::vec3(-orbit_.right().z, 0, orbit_.right().x);
  obj.position += dx * orbit_.right() + dz * forward + glm::vec3(0, dy, 0);
}

void Controls::on_key(const Event& e, float time) {
  const int held = held_index(e.code);
  if (held >= 0) {
    double& since = down_since_[static_cast<std::size_t>(held)];
    if (e.captured && e.action != Action::Release) return;
    if (e.action == Action::Press && since < 0) {
      since = e.time;
    } else if (e.action == Action::Release && since >= 0) {
      const double seconds = e.time > since ? std::max(0.0, e.time - std::max(since, frame_start_))
                                            : std::min(kTapSeconds, std::max(0.0, e.time - frame_start_));
      since = -1;
      const HeldKey& h = kHeld[static_cast<std::size_t>(held)];
      const float s = static_cast<float>(seconds);
      if (h.turn != 0 && !scene_.objects.empty())
        scene_.objects[state_.selected % scene_.objects.size()].rotation_degrees.y += h.turn * kTurnDegrees * s;
      else if (h.turn == 0)
        move_selected(h.move.x * kMoveSpeed * orbit_.distance * s, h.move.y * kMoveSpeed * orbit_.distance * s,
                      h.move.z * kMoveSpeed * orbit_.distance * s, time);
    }
    return;
  }
  if (e.captured) return;
  const bool press = e.action == Action::Press, repeat = e.action == Action::Repeat;
  const bool shift = (e.mods & mod::Shift) != 0;
  splatcl::Quality& q = scene_.quality;
  // Zoom keys repeat while held; every other key acts once per press.
  if (press || repeat) {
    if (e.code == key::Equal || e.code == key::KeypadAdd) return zoom(1);
    if (e.code == key::Minus || e.code == key::KeypadSubtract) return zoom(-1);
  }
  if (!press) return;
  switch (e.code) {
    case key::Escape: state_.quit = true; break;
    case key::Tab:
      if (!scene_.objects.empty()) {
        const std::size_t n = scene_.objects.size();
        state_.selected = shift ? (state_.selected + n - 1) % n : (state_.selected + 1) % n;
      }
      break;
    case key::Space: state_.paused = !state_.paused; break;
    case key::P: ++state_.screenshots; break;
    case key::C: q.shading = step(q.shading, {"clustered", "tiled", "brute"}, shift); break;
    case key::M: q.mode = step(q.mode, {"splats", "points"}, shift); break;
    case key::H: q.shadows = step(q.shadows, {"splat", "pixel", "off"}, shift); break;
    case key::L: q.lod_error = q.lod_error > 0 ? 0.0f : lod_on_; break;
    case key::B: q.specular = q.specular > 0 ? 0.0f : specular_on_; break;
    case key::O: state_.ambient_occlusion = !state_.ambient_occlusion; break;
    case key::A: state_.pixel_ao = !state_.pixel_ao; break;
    case key::G: state_.floor_pixels = !state_.floor_pixels; break;
    case key::S: q.antialias = q.antialias > 0 ? 0.0f : antialias_on_; break;
    case key::F: fit(time); break;
    case key::R:
      if (shift) reset_objects();
      else reset_camera();
      break;
    case key::F1: state_.panel = !state_.panel; break;
    default:
      if (e.code >= key::Num1 && e.code <= key::Num8) state_.debug_view = static_cast<present::DebugView>(e.code - key::Num1);
  }
}

void Controls::on_cursor(const Event& e, glm::ivec2 window) {
  if (have_cursor_ && !e.captured) {
    const float dx = static_cast<float>(e.x - cursor_x_), dy = static_cast<float>(e.y - cursor_y_);
    if (left_ && !shift_drag_) orbit_by(dx, dy);
    else if (left_ || right_ || middle_) pan_by(dx, dy, window.y);
  }
  if (left_ && std::hypot(e.x - press_x_, e.y - press_y_) >= kClickPixels) dragged_ = true;
  cursor_x_ = e.x, cursor_y_ = e.y, have_cursor_ = true;
}

void Controls::on_button(const Event& e, glm::ivec2 window, float time) {
  cursor_x_ = e.x, cursor_y_ = e.y, have_cursor_ = true;
  const bool press = e.action == Action::Press;
  if (e.action == Action::Release) {
    if (e.code == button::Left) {
      const bool click = left_ && !dragged_ && !e.captured && std::hypot(e.x - press_x_, e.y - press_y_) < kClickPixels;
      left_ = false;
      if (click) {
        if (const auto hit = pick(e.x, e.y, window, time)) {
          state_.selected = *hit;
          state_.message = "picked " + scene_.objects[*hit].name;
        } else {
          state_.message = "no object under the cursor";
        }
      }
    }
    if (e.code == button::Right) right_ = false;
    if (e.code == button::Middle) middle_ = false;
    return;
  }
  if (!press || e.captured) return;
  if (e.code == button::Left) {
    left_ = true, dragged_ = false, press_x_ = e.x, press_y_ = e.y;
    shift_drag_ = (e.mods & mod::Shift) != 0;
  }
  if (e.code == button::Right) right_ = true;
  if (e.code == button::Middle) middle_ = true;
}

void Controls::apply(const std::vector<Event>& events, double now, glm::ivec2 window, float time) {
  if (window.x > 0 && window.y > 0) aspect_ = static_cast<float>(window.x) / static_cast<float>(window.y);
  for (const Event& e : events) {
    switch (e.type) {
      case Event::Type::Key: on_key(e, time); break;
      case Event::Type::Button: on_button(e, window, time); break;
      case Event::Type::Cursor: on_cursor(e, window); break;
      case Event::Type::Scroll:
        if (!e.captured) zoom(static_cast<float>(e.y));
        break;
    }
  }
  // Keys still held move for the rest of the frame.
  for (std::size_t i = 0; i < kHeld.size(); ++i) {
    double& since = down_since_[i];
    if (since < 0) continue;
    const float s = static_cast<float>(std::max(0.0, now - std::max(since, frame_start_)));
    const HeldKey& h = kHeld[i];
    if (h.turn != 0) {
      if (!scene_.objects.empty()) scene_.objects[state_.selected % scene_.objects.size()].rotation_degrees.y += h.turn * kTurnDegrees * s;
    } else {
      const float d = kMoveSpeed * orbit_.distance * s;
      move_selected(h.move.x * d, h.move.y * d, h.move.z * d, time);
    }
  }
  frame_start_ = now;
  write_camera();
}

}  // namespace splatcl::cli::viewer
