// Test-scene generator, ray caster, light placement and the JSON scene form.
#include <gtest/gtest.h>

#include <cmath>

#include "cluster/test_scene.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

Scene one_sphere_scene() {
  Scene scene;
  scene.objects.push_back(Sphere{{0, 0, -10}, 2});
  scene.camera.eye = {0, 0, 0};
  scene.camera.target = {0, 0, -1};
  scene.camera.near_plane = 0.5f;
  scene.camera.far_plane = 50;
  return scene;
}

TEST(TestScene, RandomScenesAreDeterministicPerSeed) {
  EXPECT_EQ(random_scene(42), random_scene(42));
  EXPECT_NE(random_scene(42), random_scene(43));
  const Scene scene = random_scene(42, {3, 2, 5.0f, {10, 0.5f, 1.0f, 9}});
  EXPECT_EQ(scene.objects.size(), 5u);
  EXPECT_EQ(std::get<RandomLights>(scene.lights).count, 10u);
  EXPECT_EQ(scene.camera.far_plane, 50.0f);
}

TEST(TestScene, RayCastsASphereInFrontOfTheCamera) {
  const Scene scene = one_sphere_scene();
  const DepthFrame frame = ray_cast(scene, 41, 31);
  ASSERT_EQ(frame.view_z.size(), 41u * 31u);
  const std::size_t centre = 15 * 41 + 20;
  EXPECT_NEAR(frame.view_z[centre], -8.0f, 1e-4f);
  EXPECT_NEAR(frame.normals[centre].z, 1.0f, 1e-4f);  // facing the camera (+z in view space)
  EXPECT_EQ(frame.view_z[0], kBackgroundViewZ);      // corner misses
  EXPECT_EQ(frame.normals[0], Vec3{});
}

TEST(TestScene, RowZeroIsTheBottomRow) {
  Scene scene;
  scene.floor_y = -1.0f;
  scene.camera.eye = {0, 0, 0};
  scene.camera.target = {0, 0, -1};
  const DepthFrame frame = ray_cast(scene, 16, 16);
  EXPECT_LT(frame.view_z[0], 0.0f);                       // bottom row sees the floor
  EXPECT_EQ(frame.view_z[15 * 16], kBackgroundViewZ);     // top row sees the sky
  EXPECT_NEAR(frame.normals[0].y, 1.0f, 1e-5f);  // level camera: the floor normal is view +y
}

TEST(TestScene, RayCastIsTheSameForAnyThreadCount) {
  const Scene scene = random_scene(7);
  const DepthFrame one = ray_cast(scene, 64, 40, 1);
  const DepthFrame three = ray_cast(scene, 64, 40, 3);
  EXPECT_EQ(one.view_z, three.view_z);
  EXPECT_EQ(one.normals, three.normals);
}

TEST(TestScene, HonoursTheNearAndFarPlanes) {
  Scene scene = one_sphere_scene();
  scene.camera.eye = {0, 0, -9.5f};  // inside the sphere: the far side is visible
  scene.camera.target = {0, 0, -20};
  const DepthFrame inside = ray_cast(scene, 9, 9);
  EXPECT_NEAR(inside.view_z[4 * 9 + 4], -2.5f, 1e-4f);
  scene.camera.eye = {0, 0, 0};
  scene.camera.target = {0, 0, -1};
  scene.camera.far_plane = 7.0f;  // sphere beyond the far plane: nothing visible
  const DepthFrame far_clipped = ray_cast(scene, 9, 9);
  for (float z : far_clipped.view_z) EXPECT_EQ(z, kBackgroundViewZ);
}

TEST(TestScene, RandomLightsSurroundVisibleGeometry) {
  Scene scene = random_scene(3);
  scene.lights = RandomLights{500, 0.25f, 1.5f, 77};
  const DepthFrame frame = ray_cast(scene, 80, 60);
  const auto lights = view_lights(scene, frame);
  ASSERT_EQ(lights.size(), 500u);
  EXPECT_EQ(lights, view_lights(scene, frame));
  for (const auto& light : lights) {
    EXPECT_GE(light.radius, 0.25f);
    EXPECT_LT(light.radius, 1.5f);
    EXPECT_LT(light.center.z, 0.0f);
    for (float channel : {light.color.x, light.color.y, light.color.z}) {
      EXPECT_GE(channel, 0.0f);
      EXPECT_LE(channel, 1.0f);
    }
  }
  const DepthFrame empty{4, 4, std::vector<float>(16, kBackgroundViewZ), std::vector<Vec3>(16)};
  EXPECT_EQ(view_lights(scene, empty).size(), 500u);
}

TEST(TestScene, ExplicitLightsAreTransformedToViewSpace) {
  Scene scene = one_sphere_scene();
  scene.camera.eye = {1, 2, 3};
  scene.camera.target = {1, 2, 0};
  scene.lights = std::vector<SceneLight>{{{1, 2, -7}, 3.0f, {0.5f, 0.25f, 1}}};
  const auto lights = view_lights(scene, ray_cast(scene, 8, 8));
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_NEAR(lights[0].center.x, 0.0f, 1e-5f);
  EXPECT_NEAR(lights[0].center.y, 0.0f, 1e-5f);
  EXPECT_NEAR(lights[0].center.z, -10.0f, 1e-5f);
  EXPECT_EQ(lights[0].radius, 3.0f);
}

TEST(TestScene, JsonRoundTrips) {
  Scene scene = random_scene(5);
  scene.floor_y = -0.5f;
  EXPECT_EQ(nlohmann::json(scene).get<Scene>().objects, scene.objects);
  const Scene back = parse_scene(nlohmann::json(scene).dump(), "round trip");
  EXPECT_EQ(back.objects, scene.objects);
  EXPECT_EQ(back.floor_y, scene.floor_y);
  EXPECT_EQ(back.lights, scene.lights);
  EXPECT_NEAR(back.camera.fov_y, scene.camera.fov_y, 1e-6f);
  EXPECT_EQ(back.camera.eye, scene.camera.eye);

  scene.lights = std::vector<SceneLight>{{{1, 2, 3}, 4, {0.1f, 0.2f, 0.3f}}};
  scene.floor_y.reset();
  const Scene explicit_back = parse_scene(nlohmann::json(scene).dump(), "explicit");
  EXPECT_EQ(explicit_back.lights, scene.lights);
  EXPECT_FALSE(explicit_back.floor_y);
}

TEST(TestScene, ParsesTheDocumentedForm) {
  const Scene scene = parse_scene(R"({
    "floor": {"y": 0},
    "objects": [{"type": "sphere", "center": [0, 1, 0], "radius": 1},
                {"type": "box", "min": [2, 0, 2], "max": [3, 1, 3]}],
    "camera": {"eye": [0, 3, 10], "target": [0, 0, 0], "fov_y_degrees": 45, "near": 0.2, "far": 80},
    "lights": {"count": 64, "radius": [0.5, 2], "seed": 3}
  })", "inline");
  EXPECT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(std::get<Box>(scene.objects[1]).max, (Vec3{3, 1, 3}));
  EXPECT_NEAR(scene.camera.fov_y, 45.0f * 3.14159265f / 180.0f, 1e-6f);
  EXPECT_EQ(scene.camera.up, (Vec3{0, 1, 0}));
  EXPECT_EQ(std::get<RandomLights>(scene.lights), (RandomLights{64, 0.5f, 2.0f, 3}));
}

TEST(TestScene, BadScenesAreOneLineErrors) {
  const auto rejects = [](const std::string& text, const char* words) {
    try {
      parse_scene(text, "bad.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("bad.json"), std::string::npos) << message;
      EXPECT_NE(message.find(words), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  rejects("{", "invalid JSON");
  rejects("{}", "missing 'camera'");
  const std::string camera = R"("camera": {"eye": [0,0,1], "target": [0,0,0]})";
  rejects("{" + camera + R"(, "objects": [{"type": "cone"}]})", "objects[0].type");
  rejects("{" + camera + R"(, "objects": [{"type": "sphere", "center": [0,0], "radius": 1}]})", "objects[0].center");
  rejects("{" + camera + R"(, "objects": [{"type": "sphere", "center": [0,0,0], "radius": -1}]})", "radius");
  rejects(R"({"camera": {"eye": [0,0,0], "target": [0,0,0]}})", "coincide");
  rejects(R"({"camera": {"eye": [0,0,1], "target": [0,0,0], "near": 5, "far": 1}})", "near < far");
  rejects("{" + camera + R"(, "lights": {"count": -3}})", "lights.count");
  rejects("{" + camera + R"(, "lights": {"count": 3, "radius": [2, 1]}})", "lights.radius");
}

}  // namespace
}  // namespace splatcl::cluster
