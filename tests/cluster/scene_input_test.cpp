// The cluster stage's inputs from a scene: lights in view space, window depth, and the random
// scenes the other cluster tests draw.
#include <gtest/gtest.h>

#include "cluster/layout.hpp"
#include "cluster_fixture.hpp"

namespace splatcl::cluster {
namespace {

TEST(SceneInput, LightsAreTransformedToViewSpace) {
  Camera camera;
  camera.eye = {1, 2, 3};
  camera.target = {1, 2, 0};
  const std::vector<Light> lights = {{{1, 2, -7}, 3.0f, {0.5f, 0.25f, 1}, 0.0f}, {{2, 2, 3}, 1.0f, {1, 1, 1}, 0.0f}};
  const auto view = view_lights(lights, view_frame(camera));
  ASSERT_EQ(view.size(), 2u);
  EXPECT_NEAR(view[0].center.x, 0.0f, 1e-5f);
  EXPECT_NEAR(view[0].center.y, 0.0f, 1e-5f);
  EXPECT_NEAR(view[0].center.z, -10.0f, 1e-5f);
  EXPECT_EQ(view[0].radius, 3.0f);
  EXPECT_EQ(view[0].color, (Vec3{0.5f, 0.25f, 1}));
  EXPECT_NEAR(view[1].center.x, 1.0f, 1e-5f);  // one unit to the camera's right
  EXPECT_NEAR(view[1].center.z, 0.0f, 1e-5f);
}

TEST(SceneInput, WindowDepthIsTheReversedProjectionsAndZeroForBackground) {
  Camera camera;
  camera.near_plane = 0.5f;
  camera.far_plane = 50.0f;
  const std::vector<float> view_z = {kNoSurfaceViewZ, -0.5f, -5.0f, -20.0f, -50.0f, -60.0f};
  const auto depth = window_depth({6, 1, view_z, std::vector<Vec3>(6)}, camera);
  // The presenter's reversed projection (reversed_depth_projection in present/presenter.cpp) in
  // double: depth = n (f + z) / (−z (f − n)) for view z; background and beyond the far plane read 0.
  const double n = 0.5, f = 50.0;
  EXPECT_EQ(depth[0], 0.0f);
  for (std::size_t i = 1; i + 1 < view_z.size(); ++i) {
    const double expected = n * (f + view_z[i]) / (-view_z[i] * (f - n));
    EXPECT_NEAR(depth[i], expected, 1e-6) << "view z " << view_z[i];
  }
  EXPECT_EQ(depth[5], 0.0f);
}

TEST(SceneInput, RandomScenesAreDeterministicAndLitAroundTheirGeometry) {
  const auto a = testing::make_frame(42, 80, 60), b = testing::make_frame(42, 80, 60);
  EXPECT_EQ(a.depth.view_z, b.depth.view_z);
  EXPECT_EQ(a.lights, b.lights);
  EXPECT_NE(testing::make_frame(43, 80, 60).depth.view_z, a.depth.view_z);
  ASSERT_EQ(a.lights.size(), 200u);
  EXPECT_EQ(a.scene.objects.size(), 20u);
  std::size_t covered = 0;
  for (const float z : a.depth.view_z) covered += z != kNoSurfaceViewZ;
  EXPECT_GT(covered, a.depth.view_z.size() / 4);
  std::size_t in_front = 0;
  for (const auto& light : a.lights) {
    EXPECT_GE(light.radius, 0.3f);
    EXPECT_LE(light.radius, 2.5f);
    in_front += light.center.z < 0.0f;
  }
  EXPECT_GT(in_front, a.lights.size() / 2);  // most lights stand in front of the camera
}

}  // namespace
}  // namespace splatcl::cluster
