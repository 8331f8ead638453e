#include "csm/raster_capture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "primitives/launch.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {

namespace device_raster {
using uint = std::uint32_t;
using splatcl::device_trace::csm_pixel_depths;  // the single-hit rule, written once in csm_trace.h
#include "../../kernels/csm_raster.h"
}  // namespace device_raster

namespace {

using primitives::detail::set_args;

// Interleaves the low 10 bits of x, y and z.
std::uint32_t morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  const auto spread = [](std::uint32_t v) {
    v &= 0x3ffu;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

device_raster::CsmRasterCamera raster_camera(const Camera& c) {
  return {c.d[0], c.d[1], c.d[2], c.u[0], c.u[1], c.u[2], c.v[0], c.v[1], c.v[2]};
}

device_raster::CsmRasterParams raster_params(const CaptureScene& scene) {
  return {scene.resolution,  scene.sphere.radius, static_cast<float>(scene.resolution) / (2.0f * scene.sphere.radius),
          scene.half_pixel(), scene.depth_scale(), scene.hit_epsilon,
          single_hit_code(scene.single_hit)};
}

// Projected-vertex scratch kept for at most this many bytes (the maps of one launch).
constexpr std::size_t kScratchBytes = std::size_t{64} << 20;

}  // namespace

const char* to_string(CaptureMethod value) { return value == CaptureMethod::Raster ? "raster" : "raycast"; }

CaptureMethod parse_capture_method(const std::string& text) {
  if (text == "raster") return CaptureMethod::Raster;
  if (text == "raycast") return CaptureMethod::Raycast;
  throw Error("unknown capture method '" + text + "' (one of: raster, raycast)");
}

RasterMesh raster_mesh(const Mesh& mesh, Vec3 origin) {
  const std::vector<std::uint32_t> tris = casting_triangles(mesh, origin);
  const std::size_t count = tris.size() / 3;
  // Morton order of the centroids over the mesh's bounding box.
  Box box;
  for (std::uint32_t v : tris) box.add(mesh.vertices[v]);
  const Vec3 extent = box.hi - box.lo;
  const float scale = 1023.0f / std::max({extent.x, extent.y, extent.z, 1e-30f});
  std::vector<std::uint64_t> keys(count);
  for (std::size_t t = 0; t < count; ++t) {
    Vec3 c{0, 0, 0};
    for (int k = 0; k < 3; ++k) c = c + mesh.vertices[tris[3 * t + static_cast<std::size_t>(k)]];
    const Vec3 q = scale * ((1.0f / 3.0f) * c - box.lo);
    const auto cell = [](float v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0f, 1023.0f)); };
    keys[t] = (std::uint64_t{morton3(cell(q.x), cell(q.y), cell(q.z))} << 32) | t;
  }
  std::sort(keys.begin(), keys.end());
  RasterMesh out;
  out.triangles.reserve(tris.size());
  std::vector<std::uint32_t> renumber(mesh.vertices.size(), UINT32_MAX);
  for (std::uint64_t key : keys) {
    const std::size_t t = key & 0xffffffffu;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = tris[3 * t + static_cast<std::size_t>(k)];
      if (renumber[v] == UINT32_MAX) {
        renumber[v] = out.vertex_count();
        float p[3];
        relative_position(mesh, v, origin, p);
        out.vertices.insert(out.vertices.end(), p, p + 3);
      }
      out.triangles.push_back(renumber[v]);
    }
  }
  return out;
}

void raster_capture_reference(const CaptureScene& scene, const RasterMesh& mesh, const SphereGrid& grid,
                              std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2) {
  const std::vector<Camera> table = cameras(grid, first, count);
  const std::size_t pixels = scene.pixels();
  z1.assign(std::size_t{count} * pixels, 0.0f);
  z2.assign(z1.size(), 0.0f);
  const device_raster::CsmRasterParams params = raster_params(scene);
  const std::size_t workers = worker_count(count, 1);
  std::vector<std::vector<float>> scratch(workers);
  parallel_for(count, 1, [&](std::size_t map, std::size_t worker) {
    std::vector<float>& proj = scratch[worker];
    proj.resize(4 * std::size_t{mesh.vertex_count()});
    float* a = z1.data() + map * pixels;
    float* b = z2.data() + map * pixels;
    device_raster::csm_raster_project(mesh.vertices.data(), mesh.vertex_count(), raster_camera(table[map]), params, proj.data());
    device_raster::csm_raster_clear(a, b, static_cast<std::uint32_t>(pixels));
    device_raster::csm_raster_triangles(mesh.triangles.data(), mesh.triangle_count(), proj.data(), params, a, b);
    device_raster::csm_raster_finish(a, b, params);
  });
}

RasterCapture::RasterCapture(Runtime& runtime, const CaptureScene& scene, const RasterMesh& mesh, std::uint32_t max_slots)
    : runtime_(runtime),
      scene_(scene),
      vertex_count_(mesh.vertex_count()),
      triangle_count_(mesh.triangle_count()),
      cameras_(runtime, "CSM cameras") {
  const std::size_t slot_bytes = std::size_t{4} * sizeof(float) * vertex_count_;
  // Enough maps per launch to keep every compute unit busy, within the scratch budget.
  slots_ = static_cast<std::uint32_t>(std::clamp<std::size_t>(kScratchBytes / slot_bytes, 4, 256));
  if (max_slots) slots_ = std::min(slots_, max_slots);
  auto& queue = runtime.queue();
  vertices_ = runtime.buffer(CL_MEM_READ_ONLY, mesh.vertices.size() * sizeof(float), "CSM raster vertices");
  triangles_ = runtime.buffer(CL_MEM_READ_ONLY, mesh.triangles.size() * sizeof(std::uint32_t), "CSM raster triangles");
  scratch_ = runtime.buffer(CL_MEM_READ_WRITE, slot_bytes * slots_, "CSM raster projected vertices");
  queue.enqueueWriteBuffer(vertices_, CL_TRUE, 0, mesh.vertices.size() * sizeof(float), mesh.vertices.data());
  queue.enqueueWriteBuffer(triangles_, CL_TRUE, 0, mesh.triangles.size() * sizeof(std::uint32_t), mesh.triangles.data());
  kernel_ = runtime.kernel("csm_raster.cl", "csm_raster_capture");
}

cl::Event RasterCapture::capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1,
                                 cl::Buffer& z2, Profiler* profiler) {
  const std::size_t samples = std::size_t{count} * scene_.pixels();
  require_bytes(z1, samples * sizeof(float), "CSM capture z1");
  require_bytes(z2, samples * sizeof(float), "CSM capture z2");
  if (count == 0) return {};
  cameras_.assign(cameras(grid, first, count));
  const device_raster::CsmRasterParams p = raster_params(scene_);
  cl::Event last;
  for (std::uint32_t done = 0; done < count; done += slots_) {
    const std::uint32_t maps = std::min(slots_, count - done);
    set_args(kernel_, vertices_, static_cast<cl_uint>(vertex_count_), triangles_, static_cast<cl_uint>(triangle_count_), cameras_.buffer(),
             static_cast<cl_uint>(done), static_cast<cl_uint>(maps), static_cast<cl_uint>(p.resolution), p.radius, p.pixel_scale,
             p.half_pixel, p.depth_scale, p.eps, static_cast<cl_uint>(p.single_hit_rule), scratch_, z1, z2);
    last = enqueue_1d(runtime_.queue(), kernel_, maps, 1, profiler, "csm capture");
  }
  return last;
}

MapCapture::MapCapture(Runtime& runtime, const CaptureScene& scene, const Mesh& mesh, CaptureMethod method)
    : method_(method) {
  if (method == CaptureMethod::Raster) {
    mesh_ = raster_mesh(mesh, scene.sphere.centre);
    raster_ = std::make_unique<RasterCapture>(runtime, scene, mesh_);
  } else {
    raycast_ = std::make_unique<DepthCapture>(runtime, scene);
  }
}

MapCapture::~MapCapture() = default;

cl::Event MapCapture::capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1, cl::Buffer& z2,
                              Profiler* profiler) {
  return raster_ ? raster_->capture(grid, first, count, z1, z2, profiler) : raycast_->capture(grid, first, count, z1, z2, profiler);
}

void capture_reference(const CaptureScene& scene, const Mesh& mesh, CaptureMethod method, const SphereGrid& grid,
                       std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2) {
  if (method == CaptureMethod::Raster)
    raster_capture_reference(scene, raster_mesh(mesh, scene.sphere.centre), grid, first, count, z1, z2);
  else
    capture_reference(scene, grid, first, count, z1, z2);
}

}  // namespace splatcl::csm
