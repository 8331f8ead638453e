#include "csm/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/bvh.hpp"
#include "io/memory.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "core/parallel.hpp"

namespace splatcl::csm {
namespace {

CsmInfo info_for(const Mesh& mesh, const BuildOptions& o, const CaptureScene& scene) {
  CsmInfo info;
  info.resolution = o.resolution;
  info.maps = o.maps;
  info.distribution = o.distribution;
  info.order = o.order;
  info.pole = o.pole;
  info.single_hit = scene.single_hit;  // the rule taken (Auto resolved)
  info.hit_epsilon = o.hit_epsilon;
  info.capture = o.capture;
  info.sphere = scene.sphere;
  info.triangles = static_cast<std::uint32_t>(scene.bvh.triangles.size());
  info.source = std::filesystem::path(mesh.source).filename().string();
  return info;
}

// Runs `batch(first, count)` over the sequence in batches of `batch_maps`.
template <class Batch>
void for_each_batch(std::uint32_t maps, std::uint32_t batch_maps, const BuildProgress& progress, Batch batch) {
  for (std::uint32_t first = 0; first < maps; first += batch_maps) {
    const std::uint32_t count = std::min(batch_maps, maps - first);
    batch(first, count);
    if (progress) progress(first + count, maps);
  }
}

}  // namespace

std::uint32_t default_batch_maps(std::uint32_t resolution, std::uint32_t maps) {
  const std::uint64_t pixels = std::uint64_t{resolution} * resolution;
  return static_cast<std::uint32_t>(std::clamp<std::uint64_t>((std::uint64_t{1} << 23) / pixels, 1, maps));
}

HostMapCapture::HostMapCapture(const Mesh& mesh, const SphereGrid& grid, const CaptureScene& scene, CaptureMethod method,
                               Runtime* runtime, std::uint32_t batch_maps)
    : mesh_(mesh), grid_(grid), scene_(scene), method_(method), runtime_(runtime), batch_maps_(batch_maps) {
  if (!runtime) return;
  capture_ = std::make_unique<MapCapture>(*runtime, scene, mesh, method);
  const std::size_t bytes = std::size_t{batch_maps} * scene.pixels() * sizeof(float);
  d1_ = runtime->buffer(CL_MEM_READ_WRITE, bytes, "CSM host capture z1");
  d2_ = runtime->buffer(CL_MEM_READ_WRITE, bytes, "CSM host capture z2");
}

HostMapCapture::~HostMapCapture() = default;

void HostMapCapture::get(std::uint32_t first, std::uint32_t count, std::vector<float>& z1, std::vector<float>& z2) {
  if (count > batch_maps_) throw Error("HostMapCapture: more maps than one batch holds");
  if (!runtime_) return capture_reference(scene_, mesh_, method_, grid_, first, count, z1, z2);
  capture_->capture(grid_, first, count, d1_, d2_);
  z1.resize(std::size_t{count} * scene_.pixels());
  z2.resize(z1.size());
  runtime_->queue().enqueueReadBuffer(d1_, CL_FALSE, 0, z1.size() * sizeof(float), z1.data());
  runtime_->queue().enqueueReadBuffer(d2_, CL_TRUE, 0, z2.size() * sizeof(float), z2.data());
}

BuildResult build_csm(const Mesh& mesh, const BuildOptions& o, Runtime* runtime, const BuildProgress& progress) {
  Stopwatch total;
  BuildResult result;
  const SphereGrid grid(o.distribution, o.order, o.pole, o.maps);
  const CaptureScene scene(mesh, bounding_sphere(mesh), o.resolution, o.single_hit, o.hit_epsilon);
  if (!o.thin_part_remedy.empty()) result.thin_part_warning = thin_part_warning(scene, mesh, o.thin_part_remedy);
  result.batch_maps = o.batch_maps ? std::min(o.batch_maps, o.maps) : default_batch_maps(o.resolution, o.maps);
  result.setup_ms = total.elapsed_ms();
  const std::size_t pixels = scene.pixels();
  if (runtime) {
    MapCapture capture(*runtime, scene, mesh, o.capture);
    StreamingCompressor compressor(*runtime, pixels, o.maps);
    const std::size_t bytes = std::size_t{result.batch_maps} * pixels * sizeof(float);
    cl::Buffer z1 = runtime->buffer(CL_MEM_READ_WRITE, bytes, "CSM batch depths z1");
    cl::Buffer z2 = runtime->buffer(CL_MEM_READ_WRITE, bytes, "CSM batch depths z2");
    Profiler profiler;
    for_each_batch(o.maps, result.batch_maps, progress, [&](std::uint32_t first, std::uint32_t count) {
      capture.capture(grid, first, count, z1, z2, &profiler);
      compressor.add(z1, z2, count, &profiler);
      // Finishing copies what is held once, and the .csm's depths and file take about as much again
      // (a review saw a 1024² build of 256 maps admitted with 1.5 times reserved peak above it):
      // stop now, with the cause, rather than be killed for memory later (an 8192² build of 16,384
      // maps grew to 24 GB and the out-of-memory killer ended the whole batch run).
      const std::uint64_t held = compressor.held_bytes();
      require_memory(2 * held,
                     fmt::format("the CSM build at resolution {} with {} maps (its compressed maps hold {} after {} maps)",
                                 o.resolution, o.maps, memory_size(held), first + count),
                     "lower the resolution or the map count");
    });
    result.segments = compressor.finish();
    for (const auto& [label, ms] : profiler.per_label_ms()) (label == "csm capture" ? result.capture_ms : result.compress_ms) += ms;
  } else {
    require_memory(std::uint64_t{o.maps} * pixels * 2 * sizeof(float),
                   fmt::format("the reference CSM build at resolution {} with {} maps (it holds every map)", o.resolution, o.maps),
                   "lower the resolution or the map count, or use the OpenCL build");
    std::vector<float> z1(std::size_t{o.maps} * pixels), z2(z1.size()), b1, b2;
    Stopwatch capture_clock;
    for_each_batch(o.maps, result.batch_maps, progress, [&](std::uint32_t first, std::uint32_t count) {
      capture_reference(scene, mesh, o.capture, grid, first, count, b1, b2);
      std::copy(b1.begin(), b1.end(), z1.begin() + static_cast<std::ptrdiff_t>(first * pixels));
      std::copy(b2.begin(), b2.end(), z2.begin() + static_cast<std::ptrdiff_t>(first * pixels));
    });
    result.capture_ms = capture_clock.elapsed_ms();
    Stopwatch compress_clock;
    result.segments = compress_reference(z1, z2, pixels, o.maps);
    result.compress_ms = compress_clock.elapsed_ms();
  }
  result.csm = make_csm(info_for(mesh, o, scene), result.segments);
  result.total_ms = total.elapsed_ms();
  return result;
}

void require_built_from(const Csm& csm, const Mesh& mesh) {
  const CsmInfo& info = csm.info;
  const Vec3 c = info.sphere.centre;
  const float r = info.sphere.radius;
  const Sphere own = bounding_sphere(mesh);
  const std::size_t triangles = casting_triangles(mesh, c).size() / 3;
  if (length(own.centre - c) > 1e-4f * r || std::fabs(own.radius - r) > 1e-4f * r || triangles != info.triangles)
    throw Error(fmt::format("the CSM was not built from {}: its bounding sphere (centre ({:g}, {:g}, {:g}), radius {:g}) and {} "
                            "triangles against the model's (({:g}, {:g}, {:g}), {:g}) and {}",
                            mesh.source, c.x, c.y, c.z, r, info.triangles, own.centre.x, own.centre.y, own.centre.z, own.radius,
                            triangles));
}

LosslessReport check_lossless(const Csm& csm, const Mesh& model, Runtime* runtime, const BuildProgress& progress,
                              std::optional<CaptureMethod> method) {
  const CsmInfo& info = csm.info;
  // The maps were taken in object space: the model file's vertices go through the stored object
  // transform (row-major affine) first; identity leaves the model as loaded.
  std::optional<Mesh> moved;
  if (info.object_transform != CsmInfo{}.object_transform) {
    moved = model;
    for (Vec3& v : moved->vertices) v = transform_point(info.object_transform, v);
  }
  const Mesh& mesh = moved ? *moved : model;
  require_built_from(csm, mesh);
  const SphereGrid grid(info.distribution, info.order, info.pole, info.maps);
  const CaptureScene scene(mesh, info.sphere, info.resolution, info.single_hit, info.hit_epsilon);
  const std::size_t pixels = scene.pixels();
  if (csm.pixels() != pixels) throw Error("check_lossless: the CSM's pixel count does not match its resolution");
  const std::uint32_t batch_maps = default_batch_maps(info.resolution, info.maps);
  HostMapCapture capture(mesh, grid, scene, method.value_or(info.capture), runtime, batch_maps);
  // Recaptured by the other method (a cross-check), depths agree to within the two methods' errors,
  // not to the bit: a single-surface pixel's empty interval [z1, z1] (the exact rule of an open mesh)
  // failed on one-ulp differences, 8-18 % of an open sheet's samples. Each method is within the hit
  // epsilon of the surface, so two of them within twice that: on slivers (a triangle's angle of
  // 0.005 rad) the rasteriser's edge functions and the tracer's plane each lose float precision,
  // and a hemisphere scan with holes differed by 1.05e-5 of 2R at three samples.
  const float tolerance = method && *method != info.capture ? 2 * info.hit_epsilon : 0.0f;
  const auto keeps_result = [tolerance](float g, float z1, float z2) {
    if (tolerance == 0.0f || z2 == INFINITY) return lossless(g, z1, z2);
    if (z1 == z2) return std::fabs(g - z1) <= tolerance;
    return z1 - tolerance <= g && g < z2 + tolerance;
  };
  std::vector<float> z1, z2;
  // Each pixel walks its segment list forward as the maps go by: no search needed.
  std::vector<std::uint32_t> cursor(csm.offsets.begin(), csm.offsets.end() - 1);
  // Per worker: the violations, and (cross-checks only) the samples one method hits and the other
  // misses, a ray grazing a triangle's edge: a difference of the captures, not a loss of the file's,
  // unless there are many of them (a file storing "lit" over a whole surface).
  std::vector<LosslessReport> per_worker(worker_count(pixels, 64)), edges_per_worker(per_worker.size());
  const auto add = [](LosslessReport& r, std::uint32_t map, std::size_t p, float g, float a, float b) {
    if (r.violations++ == 0 || map < r.first_map) r.first_map = map, r.first_pixel = p, r.first_depth = g, r.first_z1 = a, r.first_z2 = b;
  };
  for_each_batch(info.maps, batch_maps, progress, [&](std::uint32_t first, std::uint32_t count) {
    capture.get(first, count, z1, z2);
    parallel_for(pixels, 64, [&](std::size_t p, std::size_t w) {
      LosslessReport& r = per_worker[w];
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t map = first + k;
        while (csm.end[cursor[p]] < map) ++cursor[p];
        const float g = csm.depth[cursor[p]], a = z1[std::size_t{k} * pixels + p], b = z2[std::size_t{k} * pixels + p];
        ++r.samples;
        if (keeps_result(g, a, b)) continue;
        // No hit is z1 = 1, z2 = +inf in a capture, +inf in the file.
        if (tolerance > 0 && (g == INFINITY) != (b == INFINITY)) add(edges_per_worker[w], map, p, g, a, b);
        else add(r, map, p, g, a, b);
      }
    });
  });
  LosslessReport report, edges;
  const auto merge = [](LosslessReport& into, const LosslessReport& r) {
    if (r.violations && (into.violations == 0 || r.first_map < into.first_map)) {
      into.first_map = r.first_map, into.first_pixel = r.first_pixel, into.first_depth = r.first_depth;
      into.first_z1 = r.first_z1, into.first_z2 = r.first_z2;
    }
    into.samples += r.samples;
    into.violations += r.violations;
  };
  for (const LosslessReport& r : per_worker) merge(report, r);
  for (const LosslessReport& r : edges_per_worker) merge(edges, r);
  if (edges.violations * kMostEdgeSamples > report.samples) {
    merge(report, edges);  // too many to be edges: they fail the check
  } else {
    report.edge_disagreements = edges.violations;
  }
  report.tolerance = tolerance;
  return report;
}

}  // namespace splatcl::csm
