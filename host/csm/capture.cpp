#include "csm/capture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {
namespace {

using primitives::detail::set_args;

// Vertices some face uses (load_mesh already drops unused ones; generated meshes may not).
std::vector<Vec3> face_vertices(const Mesh& mesh) {
  std::vector<std::uint32_t> used(mesh.corners);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<Vec3> out;
  out.reserve(used.size());
  for (std::uint32_t v : used) out.push_back(mesh.vertices[v]);
  return out;
}

double distance(const double c[3], Vec3 p) {
  const double dx = p.x - c[0], dy = p.y - c[1], dz = p.z - c[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double farthest(const double c[3], const std::vector<Vec3>& points) {
  double r = 0;
  for (const Vec3& p : points) r = std::max(r, distance(c, p));
  return r;
}

void pixel_depths(const CaptureScene& scene, const Camera& cam, std::uint32_t row, float* z1, float* z2) {
  const float radius = scene.trace_radius(), half_pixel = scene.trace_half_pixel(), depth_scale = scene.trace_depth_scale();
  const float eps = scene.trace_eps_distance();
  const float dir[3] = {-cam.d[0], -cam.d[1], -cam.d[2]};
  const float y = static_cast<float>(2 * row + 1) * half_pixel - radius;
  const std::uint32_t rule = single_hit_code(scene.single_hit);
  for (std::uint32_t i = 0; i < scene.resolution; ++i) {
    const float x = static_cast<float>(2 * i + 1) * half_pixel - radius;
    float o[3];
    for (int k = 0; k < 3; ++k) o[k] = radius * cam.d[k] + x * cam.u[k] + y * cam.v[k];
    const TwoHits hits = first_two_hits(scene.bvh, o, dir, cam.inv, eps);
    device_trace::csm_pixel_depths(hits.t1 * depth_scale, hits.t2 * depth_scale, x, y, radius, depth_scale, rule, &z1[i], &z2[i]);
  }
}

}  // namespace

const char* to_string(SingleHit value) {
  return value == SingleHit::Exact ? "exact" : value == SingleHit::Auto ? "auto" : value == SingleHit::Thin ? "thin" : "sphere-exit";
}

std::uint32_t single_hit_code(SingleHit rule) {
  if (rule == SingleHit::Auto) throw Error("single_hit_code: the rule is not resolved (auto)");
  return rule == SingleHit::SphereExit ? 0u : rule == SingleHit::Exact ? 1u : 2u;
}

SingleHit resolve_single_hit(SingleHit rule, const Mesh& mesh) {
  if (rule != SingleHit::Auto) return rule;
  return mesh.closed() ? SingleHit::SphereExit : SingleHit::Exact;
}

SingleHit parse_single_hit(const std::string& text) {
  if (text == "sphere-exit") return SingleHit::SphereExit;
  if (text == "exact") return SingleHit::Exact;
  if (text == "auto") return SingleHit::Auto;
  if (text == "thin") return SingleHit::Thin;
  throw Error("unknown single-hit rule '" + text + "' (one of: auto, sphere-exit, exact, thin)");
}

Sphere bounding_sphere(const Mesh& mesh) {
  const std::vector<Vec3> points = face_vertices(mesh);
  if (points.empty()) throw Error(mesh.source + ": the mesh has no faces");
  // Box sphere.
  Box box;
  for (const Vec3& p : points) box.add(p);
  double best_c[3] = {0.5 * (double{box.lo.x} + box.hi.x), 0.5 * (double{box.lo.y} + box.hi.y), 0.5 * (double{box.lo.z} + box.hi.z)};
  double best_r = farthest(best_c, points);
  // Ritter: start from a far pair, grow to cover every point.
  const double origin[3] = {points[0].x, points[0].y, points[0].z};
  Vec3 p = points[0], q = points[0];
  double far = -1;
  for (const Vec3& x : points)
    if (const double d = distance(origin, x); d > far) far = d, p = x;
  const double pc[3] = {p.x, p.y, p.z};
  far = -1;
  for (const Vec3& x : points)
    if (const double d = distance(pc, x); d > far) far = d, q = x;
  double c[3] = {0.5 * (double{p.x} + q.x), 0.5 * (double{p.y} + q.y), 0.5 * (double{p.z} + q.z)};
  double r = 0.5 * far;
  for (const Vec3& x : points) {
    const double d = distance(c, x);
    if (d <= r) continue;
    const double grown = 0.5 * (r + d), shift = (grown - r) / d;
    c[0] += (x.x - c[0]) * shift;
    c[1] += (x.y - c[1]) * shift;
    c[2] += (x.z - c[2]) * shift;
    r = grown;
  }
  r = farthest(c, points);
  if (r < best_r) {
    std::copy(c, c + 3, best_c);
    best_r = r;
  }
  Sphere sphere;
  sphere.centre = {static_cast<float>(best_c[0]), static_cast<float>(best_c[1]), static_cast<float>(best_c[2])};
  const double fc[3] = {sphere.centre.x, sphere.centre.y, sphere.centre.z};
  const double radius = farthest(fc, points);
  if (!(radius > 0) || !std::isfinite(radius)) {
    const std::string collapsed = float_step_warning(mesh);  // the vertices differ in the file, too close for floats there
    throw Error(mesh.source + ": the mesh has zero extent" + (collapsed.empty() ? " (all vertices coincide)" : ": " + collapsed));
  }
  sphere.radius = static_cast<float>(radius * (1 + 1e-5));
  if (!(sphere.radius >= kMinSphereRadius && sphere.radius <= kMaxSphereRadius))
    throw Error(fmt::format("{}: the mesh's bounding sphere has radius {:g}, outside [{:g}, {:g}] (scale the model into that range)",
                            mesh.source, sphere.radius, kMinSphereRadius, kMaxSphereRadius));
  return sphere;
}

CaptureScene::CaptureScene(const Mesh& mesh, const Sphere& sphere_, std::uint32_t resolution_, SingleHit single_hit_,
                           float hit_epsilon_)
    : sphere(sphere_),
      resolution(resolution_),
      single_hit(resolve_single_hit(single_hit_, mesh)),
      closed(single_hit_ == SingleHit::Auto && single_hit == SingleHit::SphereExit),
      hit_epsilon(hit_epsilon_) {
  if (resolution == 0 || resolution > 8192) throw Error("the map resolution must be between 1 and 8192");
  if (!(sphere.radius > 0) || !std::isfinite(sphere.radius)) throw Error("the bounding sphere's radius must be positive");
  if (!(hit_epsilon >= 0) || !std::isfinite(hit_epsilon)) throw Error("the hit epsilon must be finite and not negative");
  unit = trace_unit(sphere.radius);
  bvh = build_bvh(mesh_triangles(mesh, sphere.centre, unit));
}

SingleHitSample sample_single_hits(const CaptureScene& scene, std::uint32_t rays) {
  SingleHitSample sample;
  const float radius = scene.trace_radius(), eps = scene.trace_eps_distance();
  std::mt19937_64 random(20261208);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::uint32_t r = 0; r < rays; ++r) {
    // A uniform direction d, and a point of the disc through the centre across it.
    const double z = 2 * unit(random) - 1, phi = 2 * std::numbers::pi * unit(random), s = std::sqrt(std::max(0.0, 1 - z * z));
    const double d[3] = {s * std::cos(phi), s * std::sin(phi), z};
    const double a[3] = {std::fabs(d[0]) < 0.9 ? 1.0 : 0.0, std::fabs(d[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    double u[3] = {a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2], a[0] * d[1] - a[1] * d[0]};
    const double lu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (double& c : u) c /= lu;
    const double v[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]};
    const double rho = radius * std::sqrt(unit(random)), theta = 2 * std::numbers::pi * unit(random);
    const double x = rho * std::cos(theta), y = rho * std::sin(theta);
    float o[3], dir[3], inv[3];
    for (int k = 0; k < 3; ++k) {
      o[k] = static_cast<float>(radius * d[k] + x * u[k] + y * v[k]);
      dir[k] = static_cast<float>(-d[k]);
      inv[k] = inverse_direction(dir[k]);
    }
    const TwoHits hits = first_two_hits(scene.bvh, o, dir, inv, eps);
    if (!std::isfinite(hits.t1)) continue;
    ++sample.hitting;
    sample.single += !std::isfinite(hits.t2);
  }
  return sample;
}

std::string thin_part_warning(const CaptureScene& scene, const Mesh& mesh, std::string_view remedy) {
  if (scene.single_hit != SingleHit::SphereExit || !(scene.closed || mesh.closed())) return {};
  const SingleHitSample sample = sample_single_hits(scene);
  if (sample.single < kThinPartRays) return {};
  return fmt::format("{} of {} sample rays that hit this closed mesh ({:.3g} %) meet it only once within the hit epsilon "
                     "({:.3g} units): parts thinner than that are one surface there, stored as solid up to the bounding "
                     "sphere's exit, so receivers behind them read lit; {}",
                     sample.single, sample.hitting, 100 * sample.share(), scene.eps_distance(), remedy);
}

std::vector<Camera> cameras(const SphereGrid& grid, std::uint32_t first, std::uint32_t count) {
  std::vector<Camera> out(count);
  for (std::uint32_t k = 0; k < count; ++k) out[k] = grid.camera(first + k);
  return out;
}

void capture_reference(const CaptureScene& scene, const SphereGrid& grid, std::uint32_t first, std::uint32_t count,
                       std::vector<float>& z1, std::vector<float>& z2) {
  const std::size_t m = scene.resolution, pixels = scene.pixels();
  z1.assign(count * pixels, 0.0f);
  z2.assign(count * pixels, 0.0f);
  const std::vector<Camera> table = cameras(grid, first, count);
  parallel_for(std::size_t{count} * m, 4, [&](std::size_t item, std::size_t) {
    const std::size_t map = item / m, row = item % m;
    const std::size_t base = map * pixels + row * m;
    pixel_depths(scene, table[map], static_cast<std::uint32_t>(row), z1.data() + base, z2.data() + base);
  });
}

DepthCapture::DepthCapture(Runtime& runtime, const CaptureScene& scene)
    : runtime_(runtime), scene_(scene), cameras_(runtime, "CSM cameras") {
  const auto& bvh = scene.bvh;
  auto& queue = runtime.queue();
  nodes_ = runtime.buffer(CL_MEM_READ_ONLY, bvh.nodes.size() * sizeof(BvhNode), "CSM BVH nodes");
  triangles_ = runtime.buffer(CL_MEM_READ_ONLY, bvh.triangles.size() * sizeof(BvhTriangle), "CSM triangles");
  queue.enqueueWriteBuffer(nodes_, CL_TRUE, 0, bvh.nodes.size() * sizeof(BvhNode), bvh.nodes.data());
  queue.enqueueWriteBuffer(triangles_, CL_TRUE, 0, bvh.triangles.size() * sizeof(BvhTriangle), bvh.triangles.data());
  kernel_ = runtime.kernel("csm_capture.cl", "csm_capture");
}

cl::Event DepthCapture::capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1,
                                cl::Buffer& z2, Profiler* profiler) {
  const std::size_t samples = std::size_t{count} * scene_.pixels();
  require_bytes(z1, samples * sizeof(float), "CSM capture z1");
  require_bytes(z2, samples * sizeof(float), "CSM capture z2");
  cameras_.assign(cameras(grid, first, count));
  const std::size_t rows = std::size_t{count} * scene_.resolution;
  set_args(kernel_, nodes_, triangles_, cameras_.buffer(), static_cast<cl_uint>(scene_.resolution), static_cast<cl_uint>(rows),
           scene_.trace_radius(), scene_.trace_half_pixel(), scene_.trace_depth_scale(), scene_.trace_eps_distance(),
           static_cast<cl_uint>(single_hit_code(scene_.single_hit)), z1, z2);
  return enqueue_1d(runtime_.queue(), kernel_, rows, 0, profiler, "csm capture");
}

}  // namespace splatcl::csm
