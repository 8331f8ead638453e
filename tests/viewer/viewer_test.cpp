// The viewer's input logic (host/cli/viewer_controls.hpp) without a window, and its GLFW adapter
// (host/cli/viewer_glfw.hpp) on a real window under Xvfb (skipped without a display).
#include <gtest/gtest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cmath>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "cli/viewer_controls.hpp"
#include "cli/viewer_glfw.hpp"
#include "core/scene.hpp"

namespace {

using namespace splatcl;
using namespace splatcl::cli::viewer;

// The default scene (torus, sphere, box) with its meshes, and controls on it.
struct Fixture {
  splatcl::Scene scene = splatcl::default_scene();
  std::vector<Mesh> meshes;
  std::unique_ptr<Controls> controls;
  glm::ivec2 window{640, 480};
  Fixture() {
    for (const auto& o : scene.objects) meshes.push_back(splatcl::make_object_mesh(o.mesh, scene.directory));
    controls = std::make_unique<Controls>(scene);
    std::vector<const Mesh*> pointers;
    for (const auto& m : meshes) pointers.push_back(&m);
    controls->set_meshes(pointers);
  }
  std::vector<Event> taps(int code, int count, double t0, double spacing, int mods = 0) const {
    std::vector<Event> events;
    for (int i = 0; i < count; ++i) {
      events.push_back(Event::key_event(code, Action::Press, t0 + i * spacing, mods));
      events.push_back(Event::key_event(code, Action::Release, t0 + i * spacing + 0.5 * spacing, mods));
    }
    return events;
  }
  // Window position of a world point under the controls' camera.
  glm::vec2 to_window(const glm::vec3& p) const {
    const Camera c = controls->camera();
    const glm::mat4 view = glm::lookAt(glm::vec3(c.eye.x, c.eye.y, c.eye.z), glm::vec3(c.target.x, c.target.y, c.target.z),
                                       glm::vec3(c.up.x, c.up.y, c.up.z));
    const glm::mat4 proj = glm::perspective(c.fov_y, float(window.x) / float(window.y), c.near_plane, c.far_plane);
    const glm::vec3 w = glm::project(p, view, proj, glm::vec4(0, 0, window.x, window.y));
    return {w.x, float(window.y) - w.y};  // window coordinates: origin top left
  }
  glm::vec3 ndc(const glm::vec3& p) const {
    const Camera c = controls->camera();
    const glm::mat4 view = glm::lookAt(glm::vec3(c.eye.x, c.eye.y, c.eye.z), glm::vec3(c.target.x, c.target.y, c.target.z),
                                       glm::vec3(c.up.x, c.up.y, c.up.z));
    const glm::mat4 proj = glm::perspective(c.fov_y, float(window.x) / float(window.y), c.near_plane, c.far_plane);
    const glm::vec4 h = proj * view * glm::vec4(p, 1);
    return glm::vec3(h) / h.w;
  }
  void click(double x, double y, double t, int mods = 0) {
    controls->apply({Event::cursor(x, y, t), Event::button_event(button::Left, Action::Press, x, y, t, mods),
                     Event::button_event(button::Left, Action::Release, x, y, t + 0.01, mods)},
                    t + 0.02, window, 0);
  }
};

TEST(ViewerControls, TenTapsWithinOneFrameAreTenSteps) {
  Fixture f;
  ASSERT_EQ(f.scene.quality.shading, "clustered");
  ASSERT_EQ(f.scene.objects.size(), 3u);
  const float distance = f.controls->orbit().distance;
  std::vector<Event> events = f.taps(key::C, 10, 0.0, 0.02);  // ten taps of C within 0.2 s: one frame at 3 fps
  for (const Event& e : f.taps(key::P, 10, 0.0, 0.02)) events.push_back(e);
  for (const Event& e : f.taps(key::Tab, 10, 0.0, 0.02)) events.push_back(e);
  for (const Event& e : f.taps(key::Equal, 10, 0.0, 0.02)) events.push_back(e);
  for (const Event& e : f.taps(key::O, 3, 0.0, 0.02)) events.push_back(e);
  f.controls->apply(events, 0.3, f.window, 0);
  // clustered → tiled → brute → clustered ...: ten steps end one past clustered.
  EXPECT_EQ(f.scene.quality.shading, "tiled");
  EXPECT_EQ(f.controls->state().screenshots, 10u);
  EXPECT_EQ(f.controls->state().selected, 10u % 3u);
  EXPECT_NEAR(f.controls->orbit().distance, distance * std::pow(0.85f, 10.0f), 1e-4f);
  EXPECT_FALSE(f.controls->state().ambient_occlusion);  // three toggles
  // Shift+C steps back: out of brute force in one tap.
  f.scene.quality.shading = "brute";
  f.controls->apply(f.taps(key::C, 1, 1.0, 0.02, mod::Shift), 1.1, f.window, 0);
  EXPECT_EQ(f.scene.quality.shading, "tiled");
  f.controls->apply(f.taps(key::C, 1, 1.2, 0.02), 1.3, f.window, 0);
  EXPECT_EQ(f.scene.quality.shading, "brute");
}

TEST(ViewerControls, AutoRepeatOfAModeKeyIsNoStep) {
  Fixture f;
  std::vector<Event> events = {Event::key_event(key::C, Action::Press, 0)};
  for (int i = 0; i < 5; ++i) events.push_back(Event::key_event(key::C, Action::Repeat, 0.1 * (i + 1)));
  events.push_back(Event::key_event(key::C, Action::Release, 0.7));
  f.controls->apply(events, 0.8, f.window, 0);
  EXPECT_EQ(f.scene.quality.shading, "tiled");
  // Every mode and toggle key: one step each.
  f.controls->apply(f.taps(key::M, 1, 1, 0.1), 1.2, f.window, 0);
  f.controls->apply(f.taps(key::H, 1, 2, 0.1), 2.2, f.window, 0);
  f.controls->apply(f.taps(key::L, 1, 3, 0.1), 3.2, f.window, 0);
  f.controls->apply(f.taps(key::B, 1, 4, 0.1), 4.2, f.window, 0);
  f.controls->apply(f.taps(key::A, 1, 5, 0.1), 5.2, f.window, 0);
  f.controls->apply(f.taps(key::Num1 + 4, 1, 6, 0.1), 6.2, f.window, 0);
  f.controls->apply(f.taps(key::Space, 1, 7, 0.1), 7.2, f.window, 0);
  f.controls->apply(f.taps(key::F1, 1, 8, 0.1), 8.2, f.window, 0);
  EXPECT_EQ(f.scene.quality.mode, "points");
  EXPECT_EQ(f.scene.quality.shadows, "pixel");
  EXPECT_EQ(f.scene.quality.lod_error, 1.0f);
  EXPECT_EQ(f.scene.quality.specular, 0.5f);
  EXPECT_TRUE(f.controls->state().pixel_ao);
  EXPECT_EQ(f.controls->state().debug_view, present::DebugView::LightsPerCluster);
  EXPECT_TRUE(f.controls->state().paused);
  EXPECT_FALSE(f.controls->state().panel);
  f.controls->apply(f.taps(key::Escape, 1, 9, 0.1), 9.2, f.window, 0);
  EXPECT_TRUE(f.controls->state().quit);
}

// G and S: what the panel's "floor's AO and shadows per pixel" and "silhouette resolve" boxes set,
// also from the keyboard (the view loop hands floor_pixels to Presenter::floor_per_pixel, and the
// presenter reads quality.antialias every frame).
TEST(ViewerControls, FloorAndSilhouetteKeysToggleThePanelsSettings) {
  Fixture f;
  ASSERT_TRUE(f.controls->state().floor_pixels);
  const float depth_jump = f.scene.quality.antialias;
  ASSERT_GT(depth_jump, 0.0f);
  f.controls->apply(f.taps(key::G, 1, 0, 0.1), 0.2, f.window, 0);
  f.controls->apply(f.taps(key::S, 1, 1, 0.1), 1.2, f.window, 0);
  EXPECT_FALSE(f.controls->state().floor_pixels);
  EXPECT_EQ(f.scene.quality.antialias, 0.0f);
  // Three taps of each within one frame: three toggles each, back to where they were before the last.
  std::vector<Event> events = f.taps(key::G, 3, 2.0, 0.02);
  for (const Event& e : f.taps(key::S, 3, 2.0, 0.02)) events.push_back(e);
  f.controls->apply(events, 2.2, f.window, 0);
  EXPECT_TRUE(f.controls->state().floor_pixels);
  EXPECT_EQ(f.scene.quality.antialias, depth_jump);  // the scene's own depth jump comes back
  // A scene with the resolve off: S switches it on at the default depth jump.
  splatcl::Scene off = splatcl::default_scene();
  off.quality.antialias = 0.0f;
  Controls controls(off);
  controls.apply(f.taps(key::S, 1, 0, 0.1), 0.2, f.window, 0);
  EXPECT_EQ(off.quality.antialias, splatcl::Quality{}.antialias);
}

// A top view (no "up" in the scene: -z) orbited all round: the camera's up follows the orbit, so the
// image does not roll and never becomes parallel to the view (view quit with "camera up vector is
// parallel" when the drag reached pitch 0 at yaw 0).
TEST(ViewerControls, ATopViewOrbitsWithTheOrbitsUp) {
  splatcl::Scene scene = splatcl::parse_scene(R"({"objects": [], "camera": {"eye": [0, 8, 0], "target": [0, 0, 0]}})", "top.json", ".");
  Controls controls(scene);
  for (const float pitch : {1.4f, 0.7f, 0.0f, -0.7f})
    for (const float yaw : {0.0f, 1.5707964f, 3.1415927f}) {
      controls.orbit().pitch = pitch, controls.orbit().yaw = yaw;
      const splatcl::Camera c = controls.camera();
      ASSERT_NO_THROW(splatcl::view_frame(c)) << pitch << " " << yaw;
      const splatcl::ViewFrame frame = splatcl::view_frame(c);
      EXPECT_NEAR(frame.right.y, 0.0f, 1e-5f) << "rolled at pitch " << pitch << ", yaw " << yaw;
    }
}

TEST(ViewerControls, WheelZoomChangesTheDistanceAndTheSceneCamera) {
  Fixture f;
  const float d0 = f.controls->orbit().distance;
  const glm::vec3 target = f.controls->orbit().target;
  f.controls->apply({Event::scroll(0, 1, 0), Event::scroll(0, 1, 0.01)}, 0.1, f.window, 0);
  const float d1 = f.controls->orbit().distance;
  EXPECT_NEAR(d1, d0 * 0.85f * 0.85f, 1e-4f);
  const glm::vec3 eye(f.scene.camera.eye.x, f.scene.camera.eye.y, f.scene.camera.eye.z);
  EXPECT_NEAR(glm::length(eye - target), d1, 1e-4f);  // the scene's camera follows
  f.controls->apply({Event::scroll(0, -3, 0.2)}, 0.3, f.window, 0);
  EXPECT_GT(f.controls->orbit().distance, d0);
  // Clamped to the camera's planes: no zoom through the target.
  f.controls->apply({Event::scroll(0, 200, 0.4)}, 0.5, f.window, 0);
  EXPECT_GE(f.controls->orbit().distance, 2 * f.scene.camera.near_plane - 1e-6f);
}

TEST(ViewerControls, FitToSceneFramesTheSceneBounds) {
  Fixture f;
  // Off to the side and far away first.
  f.controls->orbit().target = {20, 5, -30};
  f.controls->orbit().distance = 45;
  for (const glm::ivec2 window : {glm::ivec2(640, 480), glm::ivec2(300, 900)}) {
    f.window = window;
    f.controls->apply(f.taps(key::F, 1, 0, 0.1), 0.2, f.window, 0);
    const Bounds b = f.controls->scene_bounds(0);
    ASSERT_FALSE(b.empty());
    float largest = 0;
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y, (c & 4) ? b.max.z : b.min.z);
      const glm::vec3 p = f.ndc(corner);
      EXPECT_LE(std::abs(p.x), 1.0f) << "corner " << c << " window " << window.x << "x" << window.y;
      EXPECT_LE(std::abs(p.y), 1.0f) << "corner " << c << " window " << window.x << "x" << window.y;
      largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
    }
    EXPECT_GT(largest, 0.5f) << "the scene fills a good part of the frame";
    const glm::vec3 centre = 0.5f * (b.min + b.max);
    EXPECT_NEAR(glm::length(f.controls->orbit().target - centre), 0.0f, 1e-4f);
  }
  // The bounds hold every vertex of every object's mesh.
  const Bounds b = f.controls->scene_bounds(0);
  for (std::size_t i = 0; i < f.meshes.size(); ++i)
    for (const Vec3& v : f.meshes[i].vertices) {
      const glm::vec3 p = glm::vec3(f.scene.objects[i].placement(0) * glm::vec4(v.x, v.y, v.z, 1));
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, b.min - 1e-4f)) && glm::all(glm::lessThanEqual(p, b.max + 1e-4f)));
    }
  EXPECT_NEAR(b.max.y, 2.0f + 0.49f, 0.05f);  // the tilted torus's top (1.2 + 1.25 sin 70°, as a box of its box)
}

TEST(ViewerControls, ResetReturnsToTheScenesCameraAndObjects) {
  Fixture f;
  const Camera start = f.scene.camera;
  const glm::vec3 sphere = f.scene.objects[1].position;
  f.controls->apply({Event::cursor(100, 100, 0), Event::button_event(button::Left, Action::Press, 100, 100, 0),
                     Event::cursor(180, 140, 0.05), Event::scroll(0, 2, 0.06),
                     Event::button_event(button::Right, Action::Press, 180, 140, 0.07), Event::cursor(220, 100, 0.08),
                     Event::button_event(button::Right, Action::Release, 220, 100, 0.09),
                     Event::button_event(button::Left, Action::Release, 180, 140, 0.1)},
                    0.2, f.window, 0);
  EXPECT_GT(std::abs(f.scene.camera.eye.x - start.eye.x), 0.1f);
  f.controls->state().selected = 1;
  f.controls->apply({Event::key_event(key::Left, Action::Press, 0.3), Event::key_event(key::Left, Action::Release, 0.8)}, 0.9, f.window, 0);
  EXPECT_GT(glm::length(f.scene.objects[1].position - sphere), 0.1f);
  f.controls->apply(f.taps(key::R, 1, 1, 0.1), 1.2, f.window, 0);
  EXPECT_NEAR(f.scene.camera.eye.x, start.eye.x, 1e-4f);
  EXPECT_NEAR(f.scene.camera.eye.y, start.eye.y, 1e-4f);
  EXPECT_NEAR(f.scene.camera.eye.z, start.eye.z, 1e-4f);
  EXPECT_NEAR(f.scene.camera.target.y, start.target.y, 1e-4f);
  EXPECT_GT(glm::length(f.scene.objects[1].position - sphere), 0.1f);  // R is the camera only
  f.controls->apply(f.taps(key::R, 1, 2, 0.1, mod::Shift), 2.2, f.window, 0);
  EXPECT_EQ(f.scene.objects[1].position, sphere);
}

TEST(ViewerControls, OrbitAndPanFollowTheMouse) {
  Fixture f;
  const Orbit o0 = f.controls->orbit();
  // Left drag 50 px right: yaw changes, target and distance stay.
  f.controls->apply({Event::cursor(300, 200, 0), Event::button_event(button::Left, Action::Press, 300, 200, 0),
                     Event::cursor(350, 200, 0.05), Event::button_event(button::Left, Action::Release, 350, 200, 0.1)},
                    0.2, f.window, 0);
  const Orbit o1 = f.controls->orbit();
  EXPECT_NEAR(o1.yaw, o0.yaw - 0.5f, 1e-5f);
  EXPECT_EQ(o1.target, o0.target);
  // Shift+left drag pans: the target moves along the view's right and up; the point under the
  // cursor stays under it (one window pixel = 2 d tan(fov/2) / height at the target).
  f.controls->apply({Event::cursor(300, 200, 1), Event::button_event(button::Left, Action::Press, 300, 200, 1, mod::Shift),
                     Event::cursor(340, 230, 1.05), Event::button_event(button::Left, Action::Release, 340, 230, 1.1, mod::Shift)},
                    1.2, f.window, 0);
  const Orbit o2 = f.controls->orbit();
  const float pixel = 2 * o1.distance * std::tan(0.5f * f.scene.camera.fov_y) / float(f.window.y);
  const glm::vec3 moved = o2.target - o1.target;
  EXPECT_NEAR(glm::dot(moved, o1.right()), -40 * pixel, 1e-4f);
  EXPECT_NEAR(glm::dot(moved, o1.up()), 30 * pixel, 1e-4f);
  EXPECT_NEAR(o2.distance, o1.distance, 1e-6f);
  EXPECT_NEAR(o2.yaw, o1.yaw, 1e-6f);
}

TEST(ViewerControls, ObjectMovesGoAlongTheViewsRightAndForward) {
  Fixture f;
  f.controls->state().selected = 1;  // the sphere (no animation)
  double t = 0;  // the events' clock runs on over the iterations
  for (const float yaw : {0.0f, 1.5707963f, 2.5f}) {
    t += 100;
    f.controls->orbit().yaw = yaw;
    const Orbit& o = f.controls->orbit();
    glm::vec3 forward = o.forward();
    forward.y = 0;
    forward = glm::normalize(forward);
    const float speed = Controls::kMoveSpeed * o.distance;
    // A tap of 0.1 s within one frame moves by 0.1 s of motion.
    glm::vec3 before = f.scene.objects[1].position;
    f.controls->apply({Event::key_event(key::Right, Action::Press, t + 10.0), Event::key_event(key::Right, Action::Release, t + 10.1)}, t + 10.3,
                      f.window, 0);
    glm::vec3 delta = f.scene.objects[1].position - before;
    EXPECT_NEAR(glm::dot(delta, o.right()), 0.1f * speed, 1e-4f) << "yaw " << yaw;
    EXPECT_NEAR(glm::length(delta - glm::dot(delta, o.right()) * o.right()), 0.0f, 1e-4f);
    // Up arrow held over three frames: forward (away from the camera) by the time it was down.
    before = f.scene.objects[1].position;
    f.controls->apply({Event::key_event(key::Up, Action::Press, t + 20.0)}, t + 20.25, f.window, 0);
    f.controls->apply({}, t + 20.5, f.window, 0);
    f.controls->apply({Event::key_event(key::Up, Action::Release, t + 20.75)}, t + 21.0, f.window, 0);
    delta = f.scene.objects[1].position - before;
    EXPECT_NEAR(glm::dot(delta, forward), 0.75f * speed, 1e-4f) << "yaw " << yaw;
    EXPECT_NEAR(glm::length(delta - glm::dot(delta, forward) * forward), 0.0f, 1e-4f);
    // PgUp: world up.
    before = f.scene.objects[1].position;
    f.controls->apply({Event::key_event(key::PageUp, Action::Press, t + 30.0), Event::key_event(key::PageUp, Action::Release, t + 30.2)},
                      t + 30.3, f.window, 0);
    delta = f.scene.objects[1].position - before;
    EXPECT_NEAR(delta.y, 0.2f * speed, 1e-4f);
    EXPECT_NEAR(glm::length(glm::vec2(delta.x, delta.z)), 0.0f, 1e-5f);
  }
  // Q turns about y by the held time.
  const float y0 = f.scene.objects[1].rotation_degrees.y;
  f.controls->apply({Event::key_event(key::Q, Action::Press, t + 40.0), Event::key_event(key::Q, Action::Release, t + 40.5)}, t + 40.6, f.window, 0);
  EXPECT_NEAR(f.scene.objects[1].rotation_degrees.y - y0, 0.5f * Controls::kTurnDegrees, 1e-3f);
  // A tap whose press and release were polled together (GLFW stamps both with the poll's time) moves
  // by kTapSeconds, or by the frame when that is shorter; it moved nothing.
  const float speed = Controls::kMoveSpeed * f.controls->orbit().distance;
  glm::vec3 before = f.scene.objects[1].position;
  f.controls->apply({Event::key_event(key::Right, Action::Press, t + 50.0), Event::key_event(key::Right, Action::Release, t + 50.0)}, t + 50.0,
                    f.window, 0);
  EXPECT_NEAR(glm::length(f.scene.objects[1].position - before), static_cast<float>(Controls::kTapSeconds) * speed, 1e-4f);
  before = f.scene.objects[1].position;
  f.controls->apply({Event::key_event(key::Right, Action::Press, t + 50.02), Event::key_event(key::Right, Action::Release, t + 50.02)},
                    t + 50.02, f.window, 0);
  EXPECT_NEAR(glm::length(f.scene.objects[1].position - before), 0.02f * speed, 1e-4f);
}

TEST(ViewerControls, AnOrbitingObjectStopsWhereItIsWhenMoved) {
  Fixture f;
  ASSERT_GT(f.scene.objects[0].animation.orbit_radius, 0);  // the torus orbits
  const float time = 3.0f;
  const glm::vec3 at = glm::vec3(f.scene.objects[0].placement(time)[3]);
  f.controls->state().selected = 0;
  f.controls->apply({Event::key_event(key::Left, Action::Press, 1.0), Event::key_event(key::Left, Action::Release, 1.01)}, 1.02, f.window,
                    time);
  EXPECT_EQ(f.scene.objects[0].animation.orbit_radius, 0);
  const glm::vec3 now = glm::vec3(f.scene.objects[0].placement(time)[3]);
  EXPECT_NEAR(glm::length(now - at), 0.01f * Controls::kMoveSpeed * f.controls->orbit().distance, 1e-4f);
}

TEST(ViewerControls, ClickingPicksTheObjectUnderThePixel) {
  Fixture f;
  // The torus at its own position: at time 0 its orbit puts it in front of the box.
  f.scene.objects[0].animation.orbit_radius = 0;
  const float time = 0;
  // A point inside each object, seen from the scene's camera: the sphere's and box's centres, a
  // point in the torus's tube (its centre is the hole).
  const glm::vec3 inside[3] = {glm::vec3(f.scene.objects[0].placement(time) * glm::vec4(0.9f, 0, 0, 1)),
                               glm::vec3(f.scene.objects[1].placement(time)[3]), glm::vec3(f.scene.objects[2].placement(time)[3])};
  for (std::size_t want : {2u, 0u, 1u}) {
    const glm::vec2 p = f.to_window(inside[want]);
    ASSERT_TRUE(p.x > 0 && p.x < float(f.window.x) && p.y > 0 && p.y < float(f.window.y));
    EXPECT_EQ(f.controls->pick(p.x, p.y, f.window, time), std::optional<std::size_t>(want)) << "object " << want;
    f.click(p.x, p.y, 1.0 + double(want));
    EXPECT_EQ(f.controls->state().selected, want);
    EXPECT_EQ(f.controls->state().message, "picked " + f.scene.objects[want].name);
  }
  // The sky: nothing; the selection stays.
  EXPECT_EQ(f.controls->pick(5, 5, f.window, time), std::nullopt);
  f.click(5, 5, 10);
  EXPECT_EQ(f.controls->state().selected, 1u);
  EXPECT_EQ(f.controls->state().message, "no object under the cursor");
  // A drag that starts and ends on an object orbits and picks nothing.
  const glm::vec2 box = f.to_window(inside[2]);
  f.controls->apply({Event::cursor(box.x, box.y, 20), Event::button_event(button::Left, Action::Press, box.x, box.y, 20),
                     Event::cursor(box.x + 30, box.y, 20.1), Event::cursor(box.x, box.y, 20.2),
                     Event::button_event(button::Left, Action::Release, box.x, box.y, 20.3)},
                    20.4, f.window, time);
  EXPECT_EQ(f.controls->state().selected, 1u);
  // After a move the pick follows the object's new placement.
  Fixture g;
  const glm::vec2 sphere = g.to_window(glm::vec3(g.scene.objects[1].placement(0)[3]));
  ASSERT_EQ(g.controls->pick(sphere.x, sphere.y, g.window, 0), std::optional<std::size_t>(1));
  g.scene.objects[1].position.y += 1.5f;
  EXPECT_NE(g.controls->pick(sphere.x, sphere.y, g.window, 0), std::optional<std::size_t>(1));
  const glm::vec2 lifted = g.to_window(glm::vec3(g.scene.objects[1].placement(0)[3]));
  EXPECT_EQ(g.controls->pick(lifted.x, lifted.y, g.window, 0), std::optional<std::size_t>(1));
}

TEST(ViewerControls, EventsThePanelCapturedAreIgnored) {
  Fixture f;
  const float d = f.controls->orbit().distance;
  std::vector<Event> events = f.taps(key::C, 2, 0, 0.01);
  Event wheel = Event::scroll(0, 3, 0.05);
  events.push_back(wheel);
  for (Event& e : events) e.captured = true;
  f.controls->apply(events, 0.1, f.window, 0);
  EXPECT_EQ(f.scene.quality.shading, "clustered");
  EXPECT_EQ(f.controls->orbit().distance, d);
  // A click on the panel picks nothing.
  const glm::vec2 sphere = f.to_window(glm::vec3(f.scene.objects[1].placement(0)[3]));
  Event press = Event::button_event(button::Left, Action::Press, sphere.x, sphere.y, 1);
  Event release = Event::button_event(button::Left, Action::Release, sphere.x, sphere.y, 1.01);
  press.captured = release.captured = true;
  f.controls->apply({press, release}, 1.1, f.window, 0);
  EXPECT_EQ(f.controls->state().selected, 0u);
}

TEST(ViewerControls, EventQueueKeepsOrderAndEmptiesOnTake) {
  EventQueue q;
  for (int i = 0; i < 100; ++i) q.push(Event::key_event(key::C, i % 2 ? Action::Release : Action::Press, i));
  EXPECT_EQ(q.size(), 100u);
  const std::vector<Event> taken = q.take();
  ASSERT_EQ(taken.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(taken[i].time, double(i));
  EXPECT_EQ(q.size(), 0u);
}

// The GLFW adapter on a real (hidden) window: the callbacks it installed are the ones GLFW calls,
// and each call is one queued event.
struct GlfwWindow {
  GLFWwindow* window = nullptr;
  GlfwWindow() {
    if (!glfwInit()) return;
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    window = glfwCreateWindow(320, 240, "viewer test", nullptr, nullptr);
  }
  ~GlfwWindow() {
    if (window) glfwDestroyWindow(window);
    glfwTerminate();
  }
};

TEST(GlfwInput, InstalledCallbacksQueueEveryEvent) {
  GlfwWindow w;
  if (!w.window) GTEST_SKIP() << "no display (viewer.glfw_adapter_xvfb runs this under Xvfb)";
  int forwarded = 0;
  bool capture = false;
  GlfwInput::Hooks hooks;
  hooks.key = [&](GLFWwindow*, int, int, int, int) { ++forwarded; };
  hooks.captured = [&](bool) { return capture; };
  {
    GlfwInput input(w.window, hooks);
    // What GLFW would call: the callbacks installed on the window.
    const GLFWkeyfun key_fn = glfwSetKeyCallback(w.window, nullptr);
    glfwSetKeyCallback(w.window, key_fn);
    const GLFWscrollfun scroll_fn = glfwSetScrollCallback(w.window, nullptr);
    glfwSetScrollCallback(w.window, scroll_fn);
    const GLFWmousebuttonfun button_fn = glfwSetMouseButtonCallback(w.window, nullptr);
    glfwSetMouseButtonCallback(w.window, button_fn);
    const GLFWcursorposfun cursor_fn = glfwSetCursorPosCallback(w.window, nullptr);
    glfwSetCursorPosCallback(w.window, cursor_fn);
    ASSERT_EQ(key_fn, &GlfwInput::on_key);
    ASSERT_EQ(scroll_fn, &GlfwInput::on_scroll);
    ASSERT_EQ(button_fn, &GlfwInput::on_button);
    ASSERT_EQ(cursor_fn, &GlfwInput::on_cursor);
    // Ten taps of C before the frame takes the queue, as glfwPollEvents would deliver them.
    for (int i = 0; i < 10; ++i) {
      key_fn(w.window, GLFW_KEY_C, 0, GLFW_PRESS, 0);
      key_fn(w.window, GLFW_KEY_C, 0, GLFW_RELEASE, 0);
    }
    scroll_fn(w.window, 0, 2);
    cursor_fn(w.window, 12, 34);
    button_fn(w.window, GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, GLFW_MOD_SHIFT);
    capture = true;
    key_fn(w.window, GLFW_KEY_M, 0, GLFW_PRESS, 0);
    key_fn(w.window, GLFW_KEY_UNKNOWN, 0, GLFW_PRESS, 0);  // forwarded, not queued
    EXPECT_EQ(forwarded, 22);
    std::vector<Event> events = input.queue().take();
    ASSERT_EQ(events.size(), 24u);
    for (int i = 0; i < 20; ++i) {
      EXPECT_EQ(events[i].type, Event::Type::Key);
      EXPECT_EQ(events[i].code, key::C);
      EXPECT_EQ(events[i].action, i % 2 ? Action::Release : Action::Press);
      EXPECT_FALSE(events[i].captured);
      if (i) {
        EXPECT_GE(events[i].time, events[i - 1].time);
      }
    }
    EXPECT_EQ(events[20].type, Event::Type::Scroll);
    EXPECT_EQ(events[20].y, 2.0);
    EXPECT_EQ(events[21].type, Event::Type::Cursor);
    EXPECT_EQ(events[21].x, 12.0);
    EXPECT_EQ(events[22].type, Event::Type::Button);
    EXPECT_EQ(events[22].code, button::Right);
    EXPECT_EQ(events[22].mods, mod::Shift);
    EXPECT_EQ(events[23].code, key::M);
    EXPECT_TRUE(events[23].captured);
    EXPECT_EQ(input.queue().size(), 0u);

    // Events delivered by one poll carry its time: a tap's press and release are one instant, which
    // the controls count as held kTapSeconds (stamped as each callback ran, they were microseconds
    // apart, and a tap moved by microseconds: a helper's audit at 2.5 fps).
    input.poll();
    key_fn(w.window, GLFW_KEY_LEFT, 0, GLFW_PRESS, 0);
    key_fn(w.window, GLFW_KEY_LEFT, 0, GLFW_RELEASE, 0);
    const std::vector<Event> tap = input.queue().take();
    ASSERT_EQ(tap.size(), 2u);
    EXPECT_EQ(tap[0].time, tap[1].time);
    EXPECT_LE(tap[0].time, glfwGetTime());

    // The queue into the controls: ten shading steps, one zoom of two wheel steps.
    splatcl::Scene scene = splatcl::default_scene();
    Controls controls(scene);
    const float d = controls.orbit().distance;
    controls.apply(events, glfwGetTime(), {320, 240}, 0);
    EXPECT_EQ(scene.quality.shading, "tiled");
    EXPECT_NEAR(controls.orbit().distance, d * 0.85f * 0.85f, 1e-4f);
    EXPECT_EQ(scene.quality.mode, "splats");  // captured by the panel
  }
  // Gone with the adapter.
  EXPECT_EQ(glfwSetKeyCallback(w.window, nullptr), nullptr);
  EXPECT_EQ(glfwGetWindowUserPointer(w.window), nullptr);
}

}  // namespace
