// The scene ray caster against the analytic surfaces its meshes approximate: depth, coverage and
// normals of a tessellated sphere, the floor plane, placements, the near and far planes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/scene.hpp"
#include "core/scene_ray_cast.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

// A camera at the origin looking down −z (view space = world space).
Scene empty_scene() {
  Scene scene;
  scene.source = "test scene";
  scene.floor.enabled = false;
  scene.camera.eye = {0, 0, 0};
  scene.camera.target = {0, 0, -1};
  scene.camera.near_plane = 0.5f;
  scene.camera.far_plane = 50;
  return scene;
}

ObjectSpec sphere(float radius, glm::vec3 position, std::uint32_t segments, std::uint32_t rings) {
  ObjectSpec o;
  o.name = "sphere";
  o.mesh.procedural = "sphere";
  o.mesh.radius = radius;
  o.mesh.segments = segments;
  o.mesh.rings = rings;
  o.position = position;
  return o;
}

ObjectSpec box(float side, glm::vec3 position) {
  ObjectSpec o;
  o.name = "box";
  o.mesh.procedural = "box";
  o.mesh.size = glm::vec3(side);
  o.mesh.rings = 2;
  o.position = position;
  return o;
}

// The pixel's ray direction with unit forward component, in double, as a pinhole camera defines it.
struct Ray {
  double x, y, z;
};
Ray pixel_ray(const Camera& camera, std::uint32_t width, std::uint32_t height, std::uint32_t px, std::uint32_t py) {
  const double tan_y = std::tan(0.5 * camera.fov_y), tan_x = tan_y * width / height;
  return {((px + 0.5) * 2.0 / width - 1.0) * tan_x, ((py + 0.5) * 2.0 / height - 1.0) * tan_y, -1.0};
}

TEST(SceneRayCast, TessellatedSphereMatchesTheAnalyticSphere) {
  Scene scene = empty_scene();
  const double r = 2.0, cz = -10.0;
  scene.objects.push_back(sphere(static_cast<float>(r), {0, 0, cz}, 64, 32));
  const std::uint32_t w = 81, h = 61;
  const DepthFrame frame = ray_cast(scene, w, h);
  ASSERT_EQ(frame.view_z.size(), std::size_t{w} * h);
  // The mesh's vertices lie on the sphere and its faces inside it, within the sagitta of its
  // coarsest step (π/32 of latitude or 2π/64 of longitude).
  const double sagitta = r * (1 - std::cos(std::numbers::pi / 32));
  std::size_t checked = 0;
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::size_t p = std::size_t{y} * w + x;
      const Ray d = pixel_ray(scene.camera, w, h, x, y);
      // |t·d − c|² = r² with c = (0, 0, cz): a t² − 2 b t + c0 = 0.
      const double a = d.x * d.x + d.y * d.y + d.z * d.z, b = d.z * cz, c0 = cz * cz - r * r;
      const double disc = b * b - a * c0;
      if (disc < 0) {
        EXPECT_EQ(frame.view_z[p], kNoSurfaceViewZ) << "pixel " << x << "," << y << " misses the sphere";
        EXPECT_EQ(frame.normals[p], Vec3{});
        continue;
      }
      const double t = (b - std::sqrt(disc)) / a;
      const double nx = t * d.x / r, ny = t * d.y / r, nz = (t * d.z - cz) / r;
      const double facing = -(nx * d.x + ny * d.y + nz * d.z) / std::sqrt(a);
      if (facing < 0.5) continue;  // near the silhouette the chordal surface may be missed
      ++checked;
      ASSERT_LT(frame.view_z[p], 0.0f) << "pixel " << x << "," << y;
      const double depth = -frame.view_z[p];
      EXPECT_GE(depth, t - 1e-4) << "pixel " << x << "," << y << ": the mesh lies inside the sphere";
      EXPECT_LE(depth, t + sagitta / facing + 1e-4) << "pixel " << x << "," << y;
      const Vec3 n = frame.normals[p];
      EXPECT_NEAR(std::sqrt(dot(n, n)), 1.0f, 1e-5f);
      EXPECT_GT(n.x * nx + n.y * ny + n.z * nz, std::cos(std::numbers::pi / 16)) << "pixel " << x << "," << y;
    }
  EXPECT_GT(checked, 250u);  // 277 pixels face the camera this well at 81 x 61
}

TEST(SceneRayCast, FloorIsThePlaneAndRowZeroIsTheBottom) {
  Scene scene = empty_scene();
  scene.floor.enabled = true;
  scene.floor.y = -1.0f;
  scene.floor.size = 1000.0f;
  const std::uint32_t w = 16, h = 16;
  const DepthFrame frame = ray_cast(scene, w, h);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::size_t p = std::size_t{y} * w + x;
      const Ray d = pixel_ray(scene.camera, w, h, x, y);
      const double t = -1.0 / d.y;  // the view distance to y = −1
      if (y >= h / 2 || t > scene.camera.far_plane) {
        EXPECT_EQ(frame.view_z[p], kNoSurfaceViewZ) << "row " << y << " sees the sky";
        continue;
      }
      EXPECT_NEAR(-frame.view_z[p], t, 1e-5 * t) << "pixel " << x << "," << y;
      EXPECT_NEAR(frame.normals[p].y, 1.0f, 1e-6f);  // level camera: the floor normal is view +y
    }
  EXPECT_LT(frame.view_z[0], 0.0f);
}

TEST(SceneRayCast, ObjectsStandWhereTheirPlacementPutsThem) {
  Scene scene = empty_scene();
  scene.objects.push_back(box(2.0f, {0, 0, -10}));
  const std::size_t centre = 4 * 9 + 4;
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[centre], -9.0f, 1e-5f);  // the front face at z = −9
  scene.objects[0].scale = 2.0f;
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[centre], -8.0f, 1e-5f);
  scene.objects[0].scale = 1.0f;
  scene.objects[0].fit.size = 4.0f;  // fitted to a 4-unit box before the placement
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[centre], -8.0f, 1e-5f);
  // An orbit about the camera's axis, a quarter turn by t = 1: out of the view.
  scene.objects[0].fit = {};
  scene.objects[0].animation.orbit_radius = 10.0f;
  scene.objects[0].animation.orbit_center = {0, 0, 0};
  scene.objects[0].animation.orbit_degrees_per_second = 90.0f;
  scene.objects[0].animation.orbit_phase_degrees = -90.0f;  // at t = 0: (0, 0, −10)
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[centre], -9.0f, 1e-4f);
  scene.time = 1.0f;  // at (10, 0, 0), beside the camera
  for (const float z : ray_cast(scene, 9, 9).view_z) EXPECT_EQ(z, kNoSurfaceViewZ);
}

TEST(SceneRayCast, HonoursTheNearAndFarPlanes) {
  Scene scene = empty_scene();
  scene.objects.push_back(box(4.0f, {0, 0, -10}));
  scene.camera.eye = {0, 0, -9.5f};  // inside the box: its far face at z = −12 is seen
  scene.camera.target = {0, 0, -20};
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[4 * 9 + 4], -2.5f, 1e-5f);
  scene.camera.eye = {0, 0, -7.6f};  // the near face 0.4 away, nearer than the near plane (0.5)
  EXPECT_NEAR(ray_cast(scene, 9, 9).view_z[4 * 9 + 4], -4.4f, 1e-5f);
  // A face exactly on the near plane is seen, as one exactly on the far plane is (it was missed).
  scene.camera.eye = {0, 0, -7.5f};
  EXPECT_EQ(ray_cast(scene, 9, 9).view_z[4 * 9 + 4], -0.5f);
  scene.camera.eye = {0, 0, -5.0f};
  scene.camera.far_plane = 3.0f;
  EXPECT_EQ(ray_cast(scene, 9, 9).view_z[4 * 9 + 4], -3.0f);
  scene.camera.far_plane = 50.0f;
  scene.camera.eye = {0, 0, 0};
  scene.camera.target = {0, 0, -1};
  scene.camera.far_plane = 7.0f;  // the box beyond the far plane: nothing visible
  for (const float z : ray_cast(scene, 9, 9).view_z) EXPECT_EQ(z, kNoSurfaceViewZ);
}

TEST(SceneRayCast, IsTheSameForAnyThreadCount) {
  const Scene scene = default_scene();
  const DepthFrame one = ray_cast(scene, 64, 40, 1);
  const DepthFrame three = ray_cast(scene, 64, 40, 3);
  EXPECT_EQ(one.view_z, three.view_z);
  EXPECT_EQ(one.normals, three.normals);
  std::size_t covered = 0;
  for (const float z : one.view_z) covered += z != kNoSurfaceViewZ;
  EXPECT_GT(covered, one.view_z.size() / 2);  // the floor and three objects fill most of the view
}

// A scene in huge or tiny units is the same picture: the caster traces in units of
// trace_unit(far plane), and scaling by a power of two is exact. In its own units a scene scaled by
// 2^50 overflowed the tracer's products and every ray missed; and a procedural box smaller than
// 1e-6 lost all its faces (its edge vertices were merged within an absolute 1e-6).
TEST(SceneRayCast, HugeAndTinyUnitsGiveTheSameFrame) {
  const auto scaled = [](float s) {
    Scene scene = empty_scene();
    scene.camera.target = {0, 0, -s};
    scene.camera.near_plane *= s;
    scene.camera.far_plane *= s;
    scene.objects.push_back(sphere(2 * s, {0, 0, -10 * s}, 32, 16));
    scene.objects.push_back(box(1.5f * s, {2.5f * s, 1 * s, -8 * s}));
    return ray_cast(scene, 48, 32);
  };
  const DepthFrame unit = scaled(1);
  std::size_t covered = 0;
  for (const float z : unit.view_z) covered += z != kNoSurfaceViewZ;
  EXPECT_GT(covered, unit.view_z.size() / 20);
  for (const float s : {std::ldexp(1.0f, 50), std::ldexp(1.0f, -50)}) {
    const DepthFrame frame = scaled(s);
    ASSERT_EQ(frame.view_z.size(), unit.view_z.size());
    for (std::size_t p = 0; p < unit.view_z.size(); ++p) ASSERT_EQ(frame.view_z[p], unit.view_z[p] * s) << "scale " << s << ", pixel " << p;
    EXPECT_EQ(frame.normals, unit.normals) << "scale " << s;
  }
}

// A far plane far beyond the scene changes nothing: the tracer's unit follows what the rays can
// reach. From the far plane alone, far = 1e32 shrank the scene to 1e-31 units and the BVH build
// recursed until the stack overflowed (a crash of `splatcl cluster`); far = 1e20 hit nothing.
TEST(SceneRayCast, AFarPlaneBeyondTheSceneGivesTheSameFrame) {
  const auto cast = [](float far_plane) {
    Scene scene = empty_scene();
    scene.camera.target = {0, 0, -1};
    scene.camera.far_plane = far_plane;
    scene.objects.push_back(sphere(2, {0, 0, -10}, 32, 16));
    scene.objects.push_back(box(1.5f, {2.5f, 1, -8}));
    return ray_cast(scene, 48, 32);
  };
  const DepthFrame near_far = cast(100);
  for (const float far_plane : {1e20f, 1e32f, 3e38f}) {
    const DepthFrame frame = cast(far_plane);
    EXPECT_EQ(frame.view_z, near_far.view_z) << far_plane;
    EXPECT_EQ(frame.normals, near_far.normals) << far_plane;
  }
}

TEST(SceneRayCast, RefusesSplatFilesAndEmptyFrames) {
  Scene scene = empty_scene();
  EXPECT_THROW(ray_cast(scene, 0, 4), Error);
  for (const float z : ray_cast(scene, 4, 4).view_z) EXPECT_EQ(z, kNoSurfaceViewZ);  // nothing to hit
  ObjectSpec splats;
  splats.name = "scan";
  splats.mesh.splat_path = "scan.ply";
  scene.objects.push_back(splats);
  try {
    ray_cast(scene, 4, 4);
    FAIL() << "a splat-file object was ray cast";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "test scene: objects[0] (scan) is a splat file: the ray caster draws meshes and the floor only");
  }
}

}  // namespace
}  // namespace splatcl
