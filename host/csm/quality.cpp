#include "csm/quality.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "core/bvh.hpp"
#include "csm/build.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {

void validate(const QualityOptions& o) {
  if (o.views == 0 || o.views > kMaxQualityViews) throw Error(fmt::format("--views {} is not a view count in 1..{}", o.views, kMaxQualityViews));
  if (o.image == 0 || o.image > kMaxQualityImage) throw Error(fmt::format("--image {} is not an image side in 1..{}", o.image, kMaxQualityImage));
  if (!(o.fov_degrees > 0 && o.fov_degrees < 180)) throw Error(fmt::format("--fov {} is not a field of view in (0, 180) degrees", o.fov_degrees));
  if (!(o.camera_distance >= 1 && o.camera_distance <= 1e6f))
    throw Error(fmt::format("--camera-distance {} is not a distance in 1..1e6 sphere radii", o.camera_distance));
  // Farther, the light vector's squared length leaves float's range (1e20 read every query as lit).
  if (!(o.light_max > 1.05f && o.light_max <= 1e6f))
    throw Error(fmt::format("--light-max {} is not a light distance in (1.05, 1e6] sphere radii", o.light_max));
  if (const std::string problem = bias_error(o.bias); !problem.empty()) throw Error(problem);
}
namespace {

float uniform01(std::mt19937& rng) { return static_cast<float>(rng() >> 8) * (1.0f / 16777216.0f); }

Vec3 random_direction(std::mt19937& rng) {
  const float y = 2 * uniform01(rng) - 1, phi = 2 * std::numbers::pi_v<float> * uniform01(rng);
  const float s = std::sqrt(std::max(0.0f, 1 - y * y));
  return {s * std::cos(phi), y, s * std::sin(phi)};
}


}  // namespace

void require_quality_csm(const Csm& csm, const Mesh& mesh) {
  for (std::size_t k = 0; k < 16; ++k)
    if (csm.info.object_transform[k] != kIdentity[k])
      throw Error("csm quality needs a CSM built from the model as loaded (identity object transform)");
  // The reference renders `mesh`: a CSM of another model gives a meaningless score.
  require_built_from(csm, mesh);
}

QualityReport measure_quality(const Csm& csm, const Mesh& mesh, const QualityOptions& options, Runtime* runtime) {
  const CsmInfo& info = csm.info;
  require_quality_csm(csm, mesh);
  validate(options);
  const Vec3 c = info.sphere.centre;
  const float r = info.sphere.radius;
  // Traced in units of trace_unit(R), as the ray-cast capture is: in the model's units the tracer
  // overflowed from R ~ 1e13 and saw no pixel.
  const float unit = trace_unit(r);
  const Bvh bvh = build_bvh(mesh_triangles(mesh, c, unit));
  // The CSM queries work relative to c too: the occluder's centre at the origin, the receivers and
  // the light relative to c (the maps' frames are directions; the object transform is the
  // identity). From world positions, which the query re-centres in float, a model moved by 2^23
  // (float steps of 1, two texels at 64²) scored 13.5 % more wrong pixels than at the origin.
  VisibilityScene scene({&csm}, {{}});
  for (float& coordinate : scene.occluders[0].centre) coordinate = 0;
  std::unique_ptr<VisibilityQueries> device;
  if (runtime) device = std::make_unique<VisibilityQueries>(*runtime, scene);
  const std::uint32_t w = options.image;
  const float tan_half = std::tan(options.fov_degrees * std::numbers::pi_v<float> / 360.0f);
  const float eps = 1e-4f * (r / unit);  // in units of `unit`
  std::mt19937 rng(options.seed);
  QualityReport report;
  for (std::uint32_t view = 0; view < options.views; ++view) {
    const Vec3 back = random_direction(rng);  // camera at c + camera_distance·R·back, looking at c
    // The reference works relative to c, where floats keep the precision of R rather than of c: at
    // coordinates far from the origin (a scan at 1e6) its ray's start 1e-4 R off the surface was
    // below the float step of the world position, and it counted surface points as shadowed.
    const Vec3 light_local = (1.05f * r + (options.light_max - 1.05f) * r * uniform01(rng)) * random_direction(rng);
    const Vec3 forward = -1.0f * back;
    const Vec3 helper = std::abs(forward.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    const Vec3 right = normalized(cross(forward, helper)), up = cross(right, forward);
    const Vec3 eye = (options.camera_distance * r / unit) * back;  // relative to c and in units of `unit`, as the BVH is
    std::vector<Vec4> receivers, lights;
    std::vector<std::uint8_t> exact_lit, facing;
    std::vector<Vec4> hit(std::size_t{w} * w), normal(hit.size());  // hit: relative to c
    parallel_for(hit.size(), 256, [&](std::size_t p, std::size_t) {
      const float x = (2 * (static_cast<float>(p % w) + 0.5f) / static_cast<float>(w) - 1) * tan_half;
      const float y = (2 * (static_cast<float>(p / w) + 0.5f) / static_cast<float>(w) - 1) * tan_half;
      const Vec3 d = normalized(forward + x * right + y * up);
      const float o[3] = {eye.x, eye.y, eye.z}, dir[3] = {d.x, d.y, d.z};
      const float inv[3] = {inverse_direction(dir[0]), inverse_direction(dir[1]), inverse_direction(dir[2])};
      const ClosestHit h = closest_hit(bvh, o, dir, inv);
      const float t = h.t;
      hit[p] = t == INFINITY ? Vec4{0, 0, 0, 0} : Vec4{unit * (eye.x + t * d.x), unit * (eye.y + t * d.y), unit * (eye.z + t * d.z), 1};
      if (t == INFINITY) return;
      const BvhTriangle& tri = bvh.triangles[h.triangle];
      Vec3 n = cross(Vec3{tri.e1[0], tri.e1[1], tri.e1[2]}, Vec3{tri.e2[0], tri.e2[1], tri.e2[2]});
      if (dot(n, d) > 0) n = -1.0f * n;  // towards the camera: the side the image shows
      normal[p] = {n.x, n.y, n.z, 0};
    });
    std::vector<Vec3> local;  // per receiver, relative to c
    for (std::size_t p = 0; p < hit.size(); ++p)
      if (hit[p].w == 1) {
        local.push_back({hit[p].x, hit[p].y, hit[p].z});
        receivers.push_back({hit[p].x, hit[p].y, hit[p].z, 1});
        lights.push_back({light_local.x, light_local.y, light_local.z, 1});
        facing.push_back(dot(Vec3{normal[p].x, normal[p].y, normal[p].z}, light_local - local.back()) > 0);
      }
    exact_lit.resize(receivers.size());
    parallel_for(receivers.size(), 256, [&](std::size_t k, std::size_t) {
      const Vec3 to_light = light_local - local[k];
      const float len = length(to_light);
      const Vec3 d = (1.0f / len) * to_light;
      const Vec3 from = (1.0f / unit) * local[k] + eps * d;
      const float o[3] = {from.x, from.y, from.z}, dir[3] = {d.x, d.y, d.z};
      exact_lit[k] = !any_hit(bvh, o, dir, len / unit - eps);
    });
    std::vector<float> vis;
    Stopwatch clock;
    Profiler profiler;
    if (device) vis = device->run(receivers, lights, options.filter, options.bias, &profiler);
    else visibility_reference(scene, receivers, lights, options.filter, options.bias, vis);
    report.query_ms += clock.elapsed_ms();
    report.kernel_ms += profiler.total_device_ms();
    for (std::size_t k = 0; k < receivers.size(); ++k) {
      const bool wrong = (vis[k] >= 0.5f) != (exact_lit[k] != 0);
      report.wrong += wrong;
      report.facing_pixels += facing[k];
      report.wrong_facing += wrong && facing[k];
      report.false_shadow_facing += wrong && facing[k] && exact_lit[k];
      report.exact_shadowed += exact_lit[k] == 0;
    }
    report.pixels += hit.size();
    report.object_pixels += receivers.size();
  }
  // Every view looks at the bounding sphere's centre from its surface: a model it bounds shows. No
  // hit at all means the reference tracer failed, and "0 % wrong of 0 pixels" would pass.
  if (report.object_pixels == 0)
    throw Error(fmt::format("{}: no view's rays hit the model (bounding sphere radius {:g}): nothing to measure", mesh.source, r));
  return report;
}

}  // namespace splatcl::csm
