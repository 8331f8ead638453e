#include "core/scene_ray_cast.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/bvh.hpp"
#include "core/camera.hpp"
#include "core/parallel.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

// Barycentric slack of the primary rays' triangle test: without it a ray exactly through an edge
// that two triangles share may miss both (a one-pixel hole on a column aligned with a meridian).
constexpr float kEdgeTolerance = 1e-5f;

// Every surface of the scene at its time: the objects' meshes placed, and the floor's square.
std::vector<Mesh> placed_meshes(const Scene& scene) {
  std::vector<Mesh> meshes;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& object = scene.objects[i];
    if (!object.mesh.splat_path.empty())
      throw Error(fmt::format("{}: objects[{}] ({}) is a splat file: the ray caster draws meshes and the floor only",
                              scene.source, i, object.name));
    // Named as render names it (a missing mesh read "cannot read mesh m.obj", no scene or object).
    Mesh mesh;
    try {
      mesh = make_fitted_mesh(object, scene.directory);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", object_where(scene, i), e.what()));
    }
    const glm::mat4 placement = object.placement(scene.time);
    for (Vec3& v : mesh.vertices) {
      const glm::vec4 p = placement * glm::vec4(v.x, v.y, v.z, 1.0f);
      v = {p.x, p.y, p.z};
    }
    meshes.push_back(std::move(mesh));
  }
  if (scene.floor.enabled) {
    const float h = 0.5f * scene.floor.size, y = scene.floor.y;
    meshes.push_back(make_mesh({{-h, y, -h}, {-h, y, h}, {h, y, h}, {h, y, -h}}, {{0, 1, 2, 3}}, "floor"));
  }
  return meshes;
}

// The surfaces relative to the camera's eye (small float error near the camera, where depth
// matters most) in units of `unit` (trace_unit: a scene in huge units would overflow the tracer's
// products).
std::vector<BvhTriangle> scene_triangles(const std::vector<Mesh>& meshes, Vec3 eye, float unit) {
  std::vector<BvhTriangle> triangles;
  for (const Mesh& mesh : meshes) {
    const std::vector<BvhTriangle> mesh_part = mesh_triangles(mesh, eye, unit);
    triangles.insert(triangles.end(), mesh_part.begin(), mesh_part.end());
  }
  return triangles;
}

// How far the surfaces reach from the eye (in double), or the far plane where that is nearer.
float traced_reach(const std::vector<Mesh>& meshes, Vec3 eye, float far_plane) {
  double reach = 0;
  for (const Mesh& mesh : meshes)
    for (const Vec3& v : mesh.vertices) {
      const double x = double{v.x} - eye.x, y = double{v.y} - eye.y, z = double{v.z} - eye.z;
      reach = std::max(reach, std::sqrt(x * x + y * y + z * z));
    }
  return reach > 0 && reach < far_plane ? static_cast<float>(reach) : far_plane;
}

}  // namespace

DepthFrame ray_cast(const Scene& scene, std::uint32_t width, std::uint32_t height, unsigned threads) {
  if (width == 0 || height == 0) throw Error("ray_cast: frame size must be at least 1x1");
  const Camera& camera = scene.camera;
  const ViewFrame frame = view_frame(camera);
  const std::vector<Mesh> meshes = placed_meshes(scene);
  // Rays reach at most the far plane or the farthest surface. From the far plane alone, a far of
  // 1e32 shrank a scene of size 10 to 1e-31 units: degenerate triangles, and the BVH build
  // recursed until the stack overflowed.
  const float unit = trace_unit(traced_reach(meshes, frame.eye, camera.far_plane));
  const Bvh bvh = build_bvh(scene_triangles(meshes, frame.eye, unit));
  const float tan_y = std::tan(0.5f * camera.fov_y);
  const float tan_x = tan_y * static_cast<float>(width) / static_cast<float>(height);

  DepthFrame result;
  result.width = width;
  result.height = height;
  result.view_z.assign(std::size_t{width} * height, kNoSurfaceViewZ);
  result.normals.assign(std::size_t{width} * height, Vec3{});
  const auto cast_row = [&](std::uint32_t y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      const float ndc_x = (static_cast<float>(x) + 0.5f) * 2.0f / static_cast<float>(width) - 1.0f;
      const float ndc_y = (static_cast<float>(y) + 0.5f) * 2.0f / static_cast<float>(height) - 1.0f;
      // A direction with unit forward component: t along it is the view distance. The ray starts
      // a few float steps before the near plane, so that nothing nearer is hit but a surface on it
      // is (the traversal takes hits at t > 0: a floor exactly on the near plane covered no pixel,
      // one on the far plane all of them); a hit within those steps lies on the near plane.
      const Vec3 d = frame.direction_to_world({ndc_x * tan_x, ndc_y * tan_y, -1.0f});
      const float dir[3] = {d.x, d.y, d.z};
      const float start = camera.near_plane * (1.0f - 0x1p-20f) / unit;
      const float origin[3] = {start * d.x, start * d.y, start * d.z};
      const float inv[3] = {inverse_direction(dir[0]), inverse_direction(dir[1]), inverse_direction(dir[2])};
      const ClosestHit hit = closest_hit(bvh, origin, dir, inv, kEdgeTolerance);
      const float distance = std::max((start + hit.t) * unit, camera.near_plane);
      if (hit.t == INFINITY || distance > camera.far_plane) continue;
      const BvhTriangle& tri = bvh.triangles[hit.triangle];
      Vec3 normal = normalized(cross(Vec3{tri.e1[0], tri.e1[1], tri.e1[2]}, Vec3{tri.e2[0], tri.e2[1], tri.e2[2]}));
      if (dot(normal, d) > 0.0f) normal = normal * -1.0f;
      const std::size_t p = std::size_t{y} * width + x;
      result.view_z[p] = -distance;
      result.normals[p] = {dot(normal, frame.right), dot(normal, frame.up), dot(normal, frame.back)};
    }
  };
  parallel_for(height, 1, [&](std::size_t y, std::size_t) { cast_row(static_cast<std::uint32_t>(y)); }, threads);
  return result;
}

}  // namespace splatcl
