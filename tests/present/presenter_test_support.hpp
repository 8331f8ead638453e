#pragma once
// Shared by the presenter tests: one headless GL context (EGL surfaceless on Mesa llvmpipe) and one
// Runtime (PoCL) per test program, a small default scene, and the splats' coverage of the mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "present/assets.hpp"
#include "present/context.hpp"
#include "present/presenter.hpp"
#include "core/scene.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::present::testing {

class PresenterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    runtime_ = Runtime::create("");
    context_ = GlContext::offscreen();
  }
  static void TearDownTestSuite() {
    context_.reset();
    runtime_.reset();
  }
  inline static std::shared_ptr<Runtime> runtime_;
  inline static std::unique_ptr<GlContext> context_;
};

// Small and quick: the default scene with its quality, fewer floor splats.
inline Scene test_scene() {
  Scene scene = default_scene();
  scene.floor.splats_per_side = 48;
  return scene;
}

// A sphere of radius 1.2 in 12 × 6 facets (30° apart) resting on the floor at the origin, alone in
// the small default scene, with a user scene's splat quality (two-sided; the default scene's thesis
// bound leaves this mesh full of holes).
inline Scene low_poly_ball_scene() {
  Scene scene = test_scene();
  ObjectSpec ball;
  ball.name = "ball";
  ball.mesh.procedural = "sphere";
  ball.mesh.radius = 1.2f, ball.mesh.segments = 12, ball.mesh.rings = 6;
  ball.position = {0.0f, 1.2f, 0.0f};
  scene.objects = {ball};
  scene.quality.sampling = "auto", scene.quality.splat_bound = "two-sided", scene.quality.eps_diagonal = 0.001f;
  return scene;
}

// The eye ray through the centre of pixel (x, y) of a width × height frame of the scene's camera
// (row 0 at the bottom, as the presenter's read-backs give the rows), and the view matrix.
struct PixelRay {
  glm::vec3 eye, dir;
  glm::mat4 view;
};
inline PixelRay pixel_ray(const Scene& scene, int width, int height, float x, float y) {
  const Camera& cam = scene.camera;
  const glm::vec3 eye(cam.eye.x, cam.eye.y, cam.eye.z);
  const glm::mat4 view = glm::lookAt(eye, {cam.target.x, cam.target.y, cam.target.z}, {cam.up.x, cam.up.y, cam.up.z});
  const glm::mat4 proj = glm::perspective(cam.fov_y, static_cast<float>(width) / static_cast<float>(height), cam.near_plane, cam.far_plane);
  const glm::vec3 far_point = glm::unProject(glm::vec3(x, y, 1.0f), view, proj, glm::vec4(0, 0, width, height));
  return {eye, glm::normalize(far_point - eye), view};
}

// The last render's splat coverage against the triangle meshes rendered with the same camera:
// covered share of the mesh pixels, and splat pixels outside the mesh relative to the mesh's.
struct Coverage {
  std::size_t mesh = 0;
  double covered = 0, spill = 0;
};
inline Coverage silhouette_coverage(Presenter& presenter, float time) {
  const auto splat_mask = presenter.read_coverage();
  const auto mesh_mask = presenter.render_mesh_mask(time);
  std::size_t covered = 0, outside = 0;
  Coverage c;
  for (std::size_t i = 0; i < mesh_mask.size(); ++i) {
    c.mesh += mesh_mask[i];
    covered += mesh_mask[i] & splat_mask[i];
    outside += splat_mask[i] & (1 - mesh_mask[i]);
  }
  c.covered = static_cast<double>(covered) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  c.spill = static_cast<double>(outside) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  return c;
}

}  // namespace splatcl::present::testing
