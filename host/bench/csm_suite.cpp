// splatcl bench csm: the coherent-shadow-map kernels on stanford-bunny — dual-depth capture (rays/s),
// streaming compression (samples/s), visibility queries (queries/s) and ambient occlusion
// (samples/s) — each on the device beside its native reference, and the capture beside Embree
// casting the same first- and second-hit rays. Sizes are modest so the suite takes under a minute.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bandwidth.hpp"
#include "bench/suites.hpp"
#include "csm/ao.hpp"
#include "csm/build.hpp"
#include "csm/capture.hpp"
#include "csm/compress.hpp"
#include "csm/raster_capture.hpp"
#include "csm/sphere_grid.hpp"
#include "csm/visibility.hpp"
#include "core/mesh.hpp"

#ifdef SPLATCL_HAVE_EMBREE
#include "bench/peers/embree.hpp"
#endif

namespace splatcl::bench {
namespace {

namespace csm = splatcl::csm;
using splatcl::Vec3;
using splatcl::Vec4;

constexpr const char* kModelName = "stanford-bunny";
constexpr const char* kModelFile = "stanford-bunny.obj";
constexpr std::uint32_t kCsmSeed = 0xC5A1u;

// Standard sizes; --quick shrinks them, --scaling size multiplies the per-case counts.
struct CsmSizes {
  std::uint32_t capture_maps, capture_resolution;  // capture and compression: maps × M² samples
  std::uint32_t query_maps, query_resolution;      // the CSM the queries and AO read
  std::uint64_t queries;                           // visibility queries per batch
  std::uint64_t ao_receivers;                      // AO receivers (× kDefaultSamples directions)
};

CsmSizes sizes_for(const Session& session) {
  CsmSizes sizes = session.options().quick ? CsmSizes{8, 32, 64, 32, 1u << 14, 1u << 10}
                                           : CsmSizes{64, 128, 1024, 64, 1u << 20, 1u << 15};
  sizes.capture_maps = static_cast<std::uint32_t>(std::min<std::uint64_t>(scaled(session, sizes.capture_maps), 1u << 16));
  sizes.queries = scaled(session, sizes.queries);
  sizes.ao_receivers = scaled(session, sizes.ao_receivers);
  return sizes;
}

void expect_same_segments(const std::string& what, const csm::Segments& actual, const csm::Segments& expected) {
  expect_same_output(what + " offsets", actual.offsets, expected.offsets);
  expect_same_output(what + " lo", actual.lo, expected.lo);
  expect_same_output(what + " hi", actual.hi, expected.hi);
  expect_same_output(what + " end", actual.end, expected.end);
}

void expect_same_vec4(const std::string& what, const std::vector<Vec4>& actual, const std::vector<Vec4>& expected) {
  if (actual.size() != expected.size() ||
      (!actual.empty() && std::memcmp(actual.data(), expected.data(), actual.size() * sizeof(Vec4)) != 0))
    throw Error("bench " + what + ": output differs from the reference");
}

csm::SphereGrid capture_grid(std::uint32_t maps) {
  // A square uniform grid holding at least `maps` maps; the capture takes its first `maps`.
  auto side = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(maps))));
  while (side * side < maps) ++side;
  return csm::SphereGrid(csm::Distribution::Uniform, csm::Order::ZigzagH, csm::PoleAxis::Y, side * side);
}

#ifdef SPLATCL_HAVE_EMBREE
// The BVH's triangles as corners relative to the sphere centre, in units of scene.unit: the same geometry both capture.
std::vector<float> triangle_corners(const Bvh& bvh) {
  std::vector<float> corners;
  corners.reserve(bvh.triangles.size() * 9);
  for (const auto& t : bvh.triangles) {
    for (int k = 0; k < 3; ++k) corners.push_back(t.v0[k]);
    for (int k = 0; k < 3; ++k) corners.push_back(t.v0[k] + t.e1[k]);
    for (int k = 0; k < 3; ++k) corners.push_back(t.v0[k] + t.e2[k]);
  }
  return corners;
}

// Embree's hits against our capture's (the reference's z1): the same pixels hit, at the same depth
// up to float error of two different intersection routines. A few grazing rays may differ.
void check_embree_capture(const std::string& what, const csm::CaptureScene& scene, const std::vector<float>& t1,
                          const std::vector<float>& z1) {
  std::size_t disagree = 0;
  const float scale = scene.trace_depth_scale();
  for (std::size_t k = 0; k < z1.size(); ++k) {
    const bool ours = z1[k] < 1.0f, theirs = t1[k] != INFINITY;
    if (ours != theirs || (ours && std::fabs(t1[k] * scale - z1[k]) > 1e-4f)) ++disagree;
  }
  if (static_cast<double>(disagree) > 0.001 * static_cast<double>(z1.size()) + 2)
    throw Error("bench " + what + ": " + std::to_string(disagree) + " of " + std::to_string(z1.size()) +
                " first hits differ from the reference capture");
}
#endif

struct CaptureOutput {
  std::vector<float> z1, z2;  // the reference's depths, [map][pixel]
};

CaptureOutput bench_capture(Session& session, const Mesh& mesh, const CsmSizes& sizes, cl::Buffer& z1,
                            cl::Buffer& z2) {
  Runtime& runtime = session.runtime();
  const csm::CaptureScene scene(mesh, csm::bounding_sphere(mesh), sizes.capture_resolution, csm::SingleHit::SphereExit);
  const csm::SphereGrid grid = capture_grid(sizes.capture_maps);
  const std::uint32_t maps = sizes.capture_maps;
  const std::uint64_t rays = std::uint64_t{maps} * scene.pixels();
  const Json problem{{"model", kModelName}, {"res", sizes.capture_resolution}};

  // Both capture methods (ray casting against the BVH, rasterization into two-layer depth buffers),
  // each on the device beside its native reference.
  const Json raycast{{"variant", "raycast"}};
  const Json raster{{"variant", "raster"}};
  CaptureOutput out;
  const Case reference = reference_case("capture", rays, "rays", problem, raycast);
  session.measure(reference, {}, [&] { csm::capture_reference(scene, grid, 0, maps, out.z1, out.z2); });

  z1 = runtime.buffer(CL_MEM_READ_WRITE, rays * sizeof(float), "bench capture z1");
  z2 = runtime.buffer(CL_MEM_READ_WRITE, rays * sizeof(float), "bench capture z2");
  csm::DepthCapture capture(runtime, scene);
  Profiler profiler;
  Case opencl{"capture", kImplOpenCL, true, rays, "rays", problem};
  opencl.extra.update(raycast);
  session.measure(opencl, {}, [&] {
    capture.capture(grid, 0, maps, z1, z2, &profiler);
    finish(runtime);
  }, &profiler);
  expect_same_output(describe(opencl) + " z1", download<float>(runtime, z1, rays), out.z1);
  expect_same_output(describe(opencl) + " z2", download<float>(runtime, z2, rays), out.z2);

  const csm::RasterMesh raster_mesh = csm::raster_mesh(mesh, scene.sphere.centre);
  std::vector<float> raster_z1, raster_z2;
  session.measure(reference_case("capture", rays, "rays", problem, raster), {},
                  [&] { csm::raster_capture_reference(scene, raster_mesh, grid, 0, maps, raster_z1, raster_z2); });
  cl::Buffer raster_out1 = runtime.buffer(CL_MEM_READ_WRITE, rays * sizeof(float), "bench raster z1");
  cl::Buffer raster_out2 = runtime.buffer(CL_MEM_READ_WRITE, rays * sizeof(float), "bench raster z2");
  csm::RasterCapture raster_capture(runtime, scene, raster_mesh);
  Case raster_case{"capture", kImplOpenCL, true, rays, "rays", problem};
  raster_case.extra.update(raster);
  Profiler raster_profiler;
  session.measure(raster_case, {}, [&] {
    raster_capture.capture(grid, 0, maps, raster_out1, raster_out2, &raster_profiler);
    finish(runtime);
  }, &raster_profiler);
  expect_same_output(describe(raster_case) + " z1", download<float>(runtime, raster_out1, rays), raster_z1);
  expect_same_output(describe(raster_case) + " z2", download<float>(runtime, raster_out2, rays), raster_z2);

#ifdef SPLATCL_HAVE_EMBREE
  const EmbreeCapturePeer embree(triangle_corners(scene.bvh));
  std::vector<EmbreeCamera> cameras;
  for (const csm::Camera& cam : csm::cameras(grid, 0, maps)) {
    EmbreeCamera e{};
    std::copy(cam.d, cam.d + 3, e.d);
    std::copy(cam.u, cam.u + 3, e.u);
    std::copy(cam.v, cam.v + 3, e.v);
    cameras.push_back(e);
  }
  std::vector<float> t1(rays), t2(rays);
  EmbreeCapturePeer::Result hits;
  Case peer{"capture", kImplEmbree, false, rays, "rays", problem};
  peer.extra["variant"] = std::string("rtcIntersect16 ") + EmbreeCapturePeer::version();
  session.measure(peer, {}, [&] {
    hits = embree.capture(cameras, sizes.capture_resolution, scene.trace_radius(), scene.trace_eps_distance(), t1.data(), t2.data());
  });
  check_embree_capture(describe(peer), scene, t1, out.z1);
  // Embree casts a second ray only where the first one hit: the rays it really traced.
  if (session.options().measure_host)
    session.last_record().extra["rays_cast"] = Json{{"first", rays}, {"second", hits.rays - rays}};
#endif
  return out;
}

void bench_compress(Session& session, const CsmSizes& sizes, const CaptureOutput& captured, const cl::Buffer& z1,
                    const cl::Buffer& z2) {
  Runtime& runtime = session.runtime();
  const std::size_t pixels = std::size_t{sizes.capture_resolution} * sizes.capture_resolution;
  const std::uint32_t maps = sizes.capture_maps;
  const std::uint64_t samples = std::uint64_t{maps} * pixels;
  // Each sample is read once: z1 and z2, 4 bytes each.
  const Json problem{{"model", kModelName}, {"res", sizes.capture_resolution}};

  csm::Segments expected;
  Case reference = reference_case("compress", samples, "samples", problem);
  reference.extra["bytes"] = samples * 8;
  session.measure(reference, {}, [&] { expected = csm::compress_reference(captured.z1, captured.z2, pixels, maps); });

  std::unique_ptr<csm::StreamingCompressor> compressor;
  csm::Segments segments;
  Profiler profiler;
  Case opencl{"compress", kImplOpenCL, true, samples, "samples", problem};
  opencl.extra["bytes"] = samples * 8;
  session.measure(
      opencl, [&] { compressor = std::make_unique<csm::StreamingCompressor>(runtime, pixels, maps); },
      [&] {
        compressor->add(z1, z2, maps, &profiler);
        segments = compressor->finish();
      },
      &profiler);
  expect_same_segments(describe(opencl), segments, expected);
}

// A coherent, screen-like batch: a W × H grid of receivers on a floor through the lower half of the
// bunny's bounding sphere, in row order, all lit by one point light above.
struct QueryBatch {
  std::vector<Vec4> receivers, lights, normals;
};

QueryBatch floor_grid(const csm::Csm& map, std::uint64_t count) {
  const Vec3 c = map.info.sphere.centre;
  const float r = map.info.sphere.radius;
  const auto width = static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(count))));
  QueryBatch batch;
  batch.receivers.reserve(count);
  for (std::uint64_t k = 0; k < count; ++k) {
    const float s = (static_cast<float>(k % width) + 0.5f) / static_cast<float>(width);
    const float t = (static_cast<float>(k / width) + 0.5f) / static_cast<float>(width);
    batch.receivers.push_back({c.x + (2 * s - 1) * 1.5f * r, c.y - 0.5f * r, c.z + (2 * t - 1) * 1.5f * r, 1});
    batch.lights.push_back({c.x + 0.3f * r, c.y + 3 * r, c.z + 0.2f * r, 1});
    batch.normals.push_back({0, 1, 0, 0});
  }
  return batch;
}

void bench_queries(Session& session, const Mesh& mesh, const CsmSizes& sizes) {
  Runtime& runtime = session.runtime();
  csm::BuildOptions options;
  options.maps = sizes.query_maps;
  options.resolution = sizes.query_resolution;
  const csm::Csm map = csm::build_csm(mesh, options, &runtime).csm;
  const csm::VisibilityScene scene({&map}, {csm::Instance{}});
  const Json problem{{"model", kModelName}, {"maps", sizes.query_maps}, {"res", sizes.query_resolution}};

  // Visibility.
  const QueryBatch batch = floor_grid(map, sizes.queries);
  const std::size_t n = batch.receivers.size();
  std::vector<float> expected;
  session.measure(reference_case("visibility", n, "queries", problem), {},
                  [&] { csm::visibility_reference(scene, batch.receivers, batch.lights, csm::Filter::None, 0.0f, expected); });

  csm::VisibilityQueries queries(runtime, scene);
  const cl::Buffer receivers = upload(runtime, batch.receivers, "bench visibility receivers");
  const cl::Buffer lights = upload(runtime, batch.lights, "bench visibility lights");
  cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(float), "bench visibility output");
  Profiler profiler;
  // Kernel only: the batch stays on the device between repetitions, as a frame's queries would.
  const Case opencl{"visibility", kImplOpenCL, true, n, "queries", problem};
  session.measure(opencl, {}, [&] {
    queries.run(receivers, lights, n, csm::Filter::None, 0.0f, out, &profiler);
    finish(runtime);
  }, &profiler);
  expect_same_output(describe(opencl), download<float>(runtime, out, n), expected);
  // End to end: host vectors in and out (upload 32 B, read back 4 B per query; the driver's buffers
  // are allocated once and reused by every repetition).
  Profiler host_io_profiler;
  std::vector<float> host_io_out;
  const Case host_io{"visibility-host-io", kImplOpenCL, true, n, "queries", problem};
  session.measure(host_io, {}, [&] {
    host_io_out = queries.run(batch.receivers, batch.lights, csm::Filter::None, 0.0f, &host_io_profiler);
  }, &host_io_profiler);
  expect_same_output(describe(host_io), host_io_out, expected);

  // Ambient occlusion: the same floor, kDefaultSamples directions per receiver.
  const QueryBatch floor = floor_grid(map, sizes.ao_receivers);
  csm::AoRequest request;
  request.positions = floor.receivers;
  request.normals = floor.normals;
  request.patterns = csm::make_patterns(csm::PatternSet::HammersleyRotated, csm::kDefaultPatterns, csm::kDefaultSamples, kCsmSeed);
  request.samples = csm::kDefaultSamples;
  request.pattern_of = csm::choose_patterns(floor.receivers.size(), csm::kDefaultPatterns, kCsmSeed);
  const std::uint64_t samples = std::uint64_t{floor.receivers.size()} * request.samples;
  std::vector<Vec4> ao_expected;
  session.measure(reference_case("ao", samples, "samples", problem), {},
                  [&] { csm::ambient_occlusion_reference(scene, request, ao_expected); });
  csm::AmbientOcclusion ao(runtime, scene);
  std::vector<Vec4> ao_out;
  Profiler ao_profiler;
  // Timed with its upload and read-back: the driver takes and returns host vectors (its buffers are
  // reused across repetitions).
  const Case ao_case{"ao", kImplOpenCL, true, samples, "samples", problem};
  session.measure(ao_case, {}, [&] { ao_out = ao.run(request, &ao_profiler); }, &ao_profiler);
  expect_same_vec4(describe(ao_case), ao_out, ao_expected);
}

}  // namespace

void check_csm_model() {
  const std::filesystem::path path = std::filesystem::path(splats_models_dir()) / kModelFile;
  if (!std::filesystem::is_directory(splats_models_dir()))
    throw Error("models directory " + splats_models_dir() + (std::filesystem::exists(splats_models_dir()) ? " is not a directory" : " does not exist") +
                " (set it with --models)");
  if (!std::filesystem::is_regular_file(path)) throw Error("bench csm: missing model " + path.string() + " (--models DIR)");
  (void)load_mesh(path.string());  // read too, as check_splats_models does
}

void run_csm_suite(Session& session) {
  check_csm_model();
  const Mesh mesh = load_mesh((std::filesystem::path(splats_models_dir()) / kModelFile).string());
  const CsmSizes sizes = sizes_for(session);
  cl::Buffer z1, z2;
  const CaptureOutput captured = bench_capture(session, mesh, sizes, z1, z2);
  bench_compress(session, sizes, captured, z1, z2);
  bench_queries(session, mesh, sizes);
  measure_ceilings(session, session.options().quick ? kQuickStreamArrayBytes : kStreamArrayBytes);
}

}  // namespace splatcl::bench
