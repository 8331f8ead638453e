// Uses splatcl as a library would be used: a radix sort on the OpenCL device checked against
// std::sort, the splats of a generated sphere checked against the sphere, and the embedded default
// scene ray cast. Exits non-zero, with a line saying why, when a result is wrong. It also includes
// a header that includes a kernel header (csm/visibility.hpp: kernels/csm_query.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <random>
#include <vector>

#include <splatcl/primitives/primitives.hpp>
#include <splatcl/runtime/runtime.hpp>
#include <splatcl/core/mesh.hpp>
#include <splatcl/core/scene_ray_cast.hpp>
#include <splatcl/csm/visibility.hpp>
#include <splatcl/splats/pipeline.hpp>

// Only the splatcl/ tree is visible: the sources' own include root (host/) stays inside the project.
#if __has_include("runtime/runtime.hpp") || __has_include("core/mesh.hpp")
#error "splatcl's unprefixed headers are on the consumer's include path"
#endif

namespace {

int fail(const char* what) {
  std::fprintf(stderr, "consumer: %s\n", what);
  return 1;
}

// A UV sphere of radius 1 about the origin: quads between the rings, triangles at the poles.
splatcl::Mesh sphere(std::uint32_t rings, std::uint32_t segments) {
  const double pi = std::acos(-1.0);
  std::vector<splatcl::Vec3> vertices{{0, 0, 1}};
  for (std::uint32_t r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (std::uint32_t s = 0; s < segments; ++s) {
      const double phi = 2 * pi * s / segments;
      vertices.push_back({static_cast<float>(std::sin(theta) * std::cos(phi)),
                          static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta))});
    }
  }
  vertices.push_back({0, 0, -1});
  const auto ring = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
  const std::uint32_t south = static_cast<std::uint32_t>(vertices.size() - 1);
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::uint32_t s = 0; s < segments; ++s) {
    faces.push_back({0, ring(1, s), ring(1, s + 1)});
    for (std::uint32_t r = 1; r + 1 < rings; ++r) faces.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)});
    faces.push_back({ring(rings - 1, s), south, ring(rings - 1, s + 1)});
  }
  return splatcl::make_mesh(vertices, faces, "sphere");
}

}  // namespace

int main() {
  try {
    const auto runtime = splatcl::Runtime::create();
    std::printf("device: %s\n", runtime->info().name.c_str());

    std::mt19937 random(7);
    std::vector<std::uint32_t> keys(100'003);
    for (std::uint32_t& key : keys) key = static_cast<std::uint32_t>(random());
    std::vector<std::uint32_t> expected = keys;
    std::sort(expected.begin(), expected.end());
    splatcl::primitives::radix_sort(*runtime, keys, nullptr, 32);
    if (keys != expected) return fail("the radix sort's output differs from std::sort's");
    std::printf("radix sort: %zu keys sorted\n", keys.size());

    const splatcl::Mesh mesh = sphere(24, 48);
    splatcl::splats::PipelineOptions options;
    options.fit.eps = 1e-2f;
    const splatcl::splats::SplatRun run = generate_splats(mesh, splatcl::splats::ColorSource{}, options, runtime.get());
    const std::vector<splatcl::splats::SplatRecord> splats = run.records();
    if (splats.empty()) return fail("no splats");
    if (splats.size() >= run.samples.size()) return fail("no fewer splats than samples");
    for (const splatcl::splats::SplatRecord& splat : splats) {
      const splatcl::Vec3 c = splat.center;
      const double radius = std::sqrt(double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z);
      // The faces lie within the unit sphere and at least cos(pi / 24) from its centre.
      if (!(radius <= 1 + 2 * options.fit.eps && radius >= 0.98)) return fail("a splat centre is off the sphere");
    }
    std::printf("splats: %zu from %zu samples on %s\n", splats.size(), run.samples.size(), run.fit_backend.c_str());

    const splatcl::DepthFrame frame = splatcl::ray_cast(splatcl::default_scene(), 32, 24);
    std::size_t covered = 0;
    for (const float z : frame.view_z) covered += z < 0;
    if (covered < frame.view_z.size() / 2) return fail("the default scene's ray cast covers less than half the frame");
    std::printf("scene: %zu of %zu pixels covered\n", covered, frame.view_z.size());
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 1;
  }
}
