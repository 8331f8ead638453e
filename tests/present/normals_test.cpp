// Phong splats in the G-buffer (splats/normal_field.hpp, the splat vertex shader): the per-pixel
// normals of a low-poly sphere against the true sphere's normal at the pixel's own surface point,
// and the default scene's box faces still flat up to their edges (no rounding across a crease).
#include <gtest/gtest.h>

#include <cstdio>

#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

double degrees_between(glm::vec3 a, glm::vec3 b) {
  return glm::degrees(std::acos(std::clamp(static_cast<double>(glm::dot(glm::normalize(a), glm::normalize(b))), -1.0, 1.0)));
}

// A sphere of 12 × 6 facets (30° apart) alone, with a user scene's quality: at each covered pixel away from the outline, the
// G-buffer normal against the true sphere's radial direction at the pixel's surface point (its
// view depth). Points mode, which writes each splat's own normal, is the flat baseline.
TEST_F(PresenterTest, PhongSplatsShadeALowPolySphereSmoothly) {
  Scene scene = low_poly_ball_scene();
  const ObjectSpec& ball = scene.objects[0];
  scene.floor.enabled = false;
  scene.camera.eye = {0.0f, 2.4f, 3.6f}, scene.camera.target = {0.0f, 1.2f, 0.0f};
  const int width = 160, height = 120;
  // 0: splats, 1: points (flat), 2: splats with LOD at 12 pixels (the LOD tree's nodes have fields too).
  double mean[3] = {0, 0, 0}, worst[3] = {0, 0, 0};
  std::size_t pixels[3] = {0, 0, 0};
  std::uint32_t drawn[3] = {0, 0, 0};
  for (const int mode : {0, 1, 2}) {
    scene.quality.mode = mode == 1 ? "points" : "splats";
    scene.quality.lod_error = mode == 2 ? 12.0f : 0.0f;
    Presenter presenter(scene, *runtime_, width, height, SPLATCL_TEST_CACHE);
    drawn[mode] = presenter.render(0.0f).splats;
    const std::vector<float> view_z = presenter.read_view_z(), normals = presenter.read_normals();
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x);
        if (view_z[p] == 0.0f) continue;
        const PixelRay ray = pixel_ray(scene, width, height, static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        const float along = (ray.view * glm::vec4(ray.dir, 0.0f)).z;
        const glm::vec3 point = ray.eye + ray.dir * (view_z[p] / along);
        const glm::vec3 truth = glm::normalize(point - ball.position);
        if (glm::dot(truth, -ray.dir) < 0.3f) continue;  // the outline blends splats of both sides
        const double error = degrees_between({normals[3 * p], normals[3 * p + 1], normals[3 * p + 2]}, truth);
        mean[mode] += error, worst[mode] = std::max(worst[mode], error), ++pixels[mode];
      }
    mean[mode] /= static_cast<double>(std::max<std::size_t>(pixels[mode], 1));
  }
  std::printf("low-poly sphere, G-buffer normal against the true sphere: Phong splats mean %.2f° (worst %.2f°) over %zu pixels; "
              "flat splats (points mode) mean %.2f° (worst %.2f°); LOD at 12 px, %u of %u splats drawn: mean %.2f° (worst %.2f°)\n",
              mean[0], worst[0], pixels[0], mean[1], worst[1], drawn[2], drawn[0], mean[2], worst[2]);
  ASSERT_GT(pixels[0], 2000u);
  EXPECT_LT(mean[0], 0.5);
  EXPECT_LT(mean[0], 0.1 * mean[1]);
  EXPECT_LT(worst[0], 4.0);
  EXPECT_LT(drawn[2], drawn[0] / 2);
  EXPECT_LT(mean[2], 0.25 * mean[1]);
}

// The default scene's box (per-splat colours, 20 cells per face, turned 30° about y) alone: every
// covered pixel's normal is one of its faces' normals, but along the edges and the outline, where
// splats of two faces blend in one pixel. A field fitted across the crease would round the faces
// off towards their edges.
TEST_F(PresenterTest, PhongSplatsKeepTheBoxFacesFlat) {
  Scene scene = test_scene();
  for (const ObjectSpec& object : scene.objects)
    if (object.name == "box") scene.objects = {object};
  ASSERT_EQ(scene.objects.size(), 1u);
  scene.floor.enabled = false;
  const glm::vec3 at = scene.objects[0].position;
  scene.camera.eye = {at.x + 1.6f, at.y + 1.8f, at.z + 2.6f}, scene.camera.target = {at.x, at.y, at.z};
  const int width = 160, height = 120;
  Presenter presenter(scene, *runtime_, width, height, SPLATCL_TEST_CACHE);
  presenter.render(0.0f);
  const std::vector<float> normals = presenter.read_normals();
  const glm::mat3 turn(scene.objects[0].placement(0.0f));
  std::size_t covered = 0, off = 0;
  for (std::size_t p = 0; p < normals.size() / 3; ++p) {
    const glm::vec3 n(normals[3 * p], normals[3 * p + 1], normals[3 * p + 2]);
    if (glm::length(n) == 0.0f) continue;
    ++covered;
    double nearest = 180;
    for (const glm::vec3 axis : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)})
      nearest = std::min({nearest, degrees_between(n, turn * axis), degrees_between(n, -(turn * axis))});
    off += nearest > 0.5;
  }
  std::printf("box alone: %zu of %zu covered pixels more than 0.5° off every face normal\n", off, covered);
  ASSERT_GT(covered, 1500u);
  EXPECT_LT(off, covered / 40);
}

}  // namespace
}  // namespace splatcl::present
