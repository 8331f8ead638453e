#pragma once
// Dual-depth capture (Talpe ch. 4 and §5.1.2; Müller §5.2.2): for every map of a SphereGrid, an
// M × M orthographic depth map pair (z1 = first surface, z2 = next distinct surface) by ray
// casting against a host-built SAH BVH. DepthCapture runs kernels/csm_capture.cl; capture_reference
// is the native multithreaded reference with the same float operations.
//
// Depth: linear, 0 on the camera plane (tangent to the bounding sphere) and 1 at distance 2R.
// Pixel (i, j) of a map is the ray through x = (2i + 1)·R/M − R along u, y likewise along v;
// index j·M + i, row 0 at the bottom.
// Rules (documented in docs/formats.md):
// - empty pixel (no hit): z1 = 1, z2 = +inf; runs of empty pixels store +inf (always lit);
// - single-surface pixel (open mesh, or a ray grazing one triangle): SingleHit::SphereExit sets z2
//   to the depth where the ray leaves the bounding sphere (Talpe §5.1.2, its second workaround);
//   SingleHit::Exact sets z2 = z1, so the pixel keeps its own first depth (Müller §5.2.2, "ONE").
//   SingleHit::Auto (the default) takes Exact for a mesh that is not closed (Mesh::closed: a sheet,
//   a scan with holes, a soup of splat discs) and SphereExit for a closed one: behind a sheet
//   nothing is solid, so a z2 at the sphere's exit lit every receiver in the first half of that
//   span (a 4 × 4 sheet 1 above a ground plane gave AO 1.0 where ray casting gives 0.17). The
//   capture scene holds, and the file records, the rule taken.
// - SingleHit::Thin (never chosen by Auto): z2 = z1 on every pixel, also where the ray meets a
//   second surface. An open mesh that encloses air (a bowl, a roof) has no solid between two hits,
//   and a receiver in that air read as lit under the span; this costs the span's compression.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/device_vector.hpp"
#include "core/bvh.hpp"
#include "csm/sphere_grid.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"

namespace splatcl::csm {

enum class SingleHit : std::uint32_t { SphereExit = 0, Exact = 1, Auto = 2, Thin = 3 };
const char* to_string(SingleHit value);
// The capture kernels' code for a resolved rule (their single_hit_rule argument): 0 sphere-exit,
// 1 exact, 2 thin.
std::uint32_t single_hit_code(SingleHit rule);
SingleHit parse_single_hit(const std::string& text);
// The rule a capture of `mesh` takes: `rule`, or for Auto Exact or SphereExit by Mesh::closed.
SingleHit resolve_single_hit(SingleHit rule, const Mesh& mesh);

struct Sphere {
  Vec3 centre;
  float radius = 0;
};

// The bounding-sphere radii a CSM is built and read with: its depth math squares and inverts
// distances of this size in float (a file claiming 3e38 or 1e-38 made every query lit).
inline constexpr float kMinSphereRadius = 1e-18f, kMaxSphereRadius = 1e18f;

// A tight sphere around every vertex some face uses: the smaller of Ritter's sphere and the box
// sphere (box centre, farthest vertex), widened by 1e-5 of the radius so that every triangle lies
// strictly inside in float arithmetic. Throws Error for a mesh of zero extent, or one whose radius
// is outside [kMinSphereRadius, kMaxSphereRadius].
Sphere bounding_sphere(const Mesh& mesh);

// Default hit tolerance, in depth units (fraction of 2R): hits closer than this are one surface.
inline constexpr float kDefaultHitEpsilon = 1e-5f;

// Everything the capture needs, shared by the kernel driver and the reference.
struct CaptureScene {
  CaptureScene(const Mesh& mesh, const Sphere& sphere, std::uint32_t resolution, SingleHit single_hit,
               float hit_epsilon = kDefaultHitEpsilon);
  Sphere sphere;
  std::uint32_t resolution;
  SingleHit single_hit;  // resolved: never Auto
  bool closed = false;    // Mesh::closed where Auto resolved it (sphere-exit), else not computed (false)
  float hit_epsilon;  // depth units
  // The ray caster's length unit (trace_unit(R), core/bvh.hpp): in object units every pixel of a
  // torus at 3e14 came out empty.
  float unit = 1;
  Bvh bvh;  // relative to sphere.centre, in units of `unit`

  // Object units (the raster capture).
  float half_pixel() const { return sphere.radius / static_cast<float>(resolution); }
  float depth_scale() const { return 1.0f / (2.0f * sphere.radius); }
  float eps_distance() const { return hit_epsilon * 2.0f * sphere.radius; }
  // Units of `unit` (the ray caster and bvh).
  float trace_radius() const { return sphere.radius / unit; }
  float trace_half_pixel() const { return trace_radius() / static_cast<float>(resolution); }
  float trace_depth_scale() const { return 1.0f / (2.0f * trace_radius()); }
  float trace_eps_distance() const { return hit_epsilon * 2.0f * trace_radius(); }
  std::size_t pixels() const { return std::size_t{resolution} * resolution; }
};

// Parts of a closed mesh thinner than the hit epsilon (docs/formats.md, "Limit (closed parts thinner
// than the hit epsilon)"): a ray through such a part meets the mesh once, and the sphere-exit rule
// stores it as solid up to the bounding sphere's exit, so receivers behind it read lit (a 100 x 100
// x 0.001 plate 0.3 above a floor: AO 0.70-0.80 under it against 0.00-0.02 ray-cast). Of `rays`
// sample rays through the bounding sphere (uniform directions, uniform over its cross-section;
// fixed seed), those that hit the mesh, and those that meet it only once within the hit epsilon.
struct SingleHitSample {
  std::uint32_t hitting = 0, single = 0;
  double share() const { return hitting ? static_cast<double>(single) / hitting : 0.0; }
};
SingleHitSample sample_single_hits(const CaptureScene& scene, std::uint32_t rays = 16384);
// For a closed mesh captured with sphere-exit, the warning when at least kThinPartRays of the
// sample rays meet it only once: how many of those that hit it, the hit epsilon in model units,
// then `remedy` (the caller's spelling of the hit epsilon and the exact rule); empty otherwise: for
// every other rule, which stores no solid span for one hit, and for an open mesh given sphere-exit
// by name (its documented behaviour, not a thin part). A count, not a share: a 0.4 x 0.4 tab 1e-7
// thick beside a unit cube is under 0.5 % of the hitting rays; a closed mesh's grazing rays that
// meet it once lie within the hit epsilon of its outline, fewer than 8 on every shared model.
inline constexpr std::uint32_t kThinPartRays = 8;
std::string thin_part_warning(const CaptureScene& scene, const Mesh& mesh, std::string_view remedy);

// The cameras of sequence positions [first, first + count).
std::vector<Camera> cameras(const SphereGrid& grid, std::uint32_t first, std::uint32_t count);

// Native reference: depths of maps [first, first + count) in sequence order, laid out
// [map][pixel], multithreaded over pixel rows.
void capture_reference(const CaptureScene& scene, const SphereGrid& grid, std::uint32_t first, std::uint32_t count,
                       std::vector<float>& z1, std::vector<float>& z2);

// The capture kernel's driver; owns the BVH and camera buffers on the device.
class DepthCapture {
 public:
  DepthCapture(Runtime& runtime, const CaptureScene& scene);
  // Captures maps [first, first + count) into z1 and z2 (each at least count·M² floats), laid out
  // [map][pixel]. Enqueued on the runtime's queue; returns the kernel's event.
  cl::Event capture(const SphereGrid& grid, std::uint32_t first, std::uint32_t count, cl::Buffer& z1, cl::Buffer& z2,
                    Profiler* profiler = nullptr);

 private:
  Runtime& runtime_;
  const CaptureScene& scene_;
  cl::Buffer nodes_, triangles_;
  DeviceVector<Camera> cameras_;
  cl::Kernel kernel_;
};

}  // namespace splatcl::csm
