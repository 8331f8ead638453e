#pragma once
// `splatcl splats verify`: the two-sided bound between a splat set and the mesh surface, measured
// on the surface itself and independent of how the splats were built. For a tolerance ε:
//  (A) every point of every splat's ellipse (as written, after clipping) lies within ε of the
//      surface: checked on area-uniform points of each (clipped) ellipse, its rim and its clip chord;
//  (B) every point of the surface lies within ε of a splat whose ellipse contains its projection
//      along the splat normal, on the kept side of the clip line, and whose normal faces the same
//      way as the surface there: checked on area-uniform random points of the surface.
// Both sides are computed in double; a relative slack (default 1e-4) absorbs float storage.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mesh.hpp"
#include "splats/splat_file.hpp"

namespace splatcl::splats {

struct SurfaceCheckOptions {
  double eps = 0;
  std::size_t surface_points = 0;   // 0: default_surface_points(area, eps)
  std::size_t ellipse_points = 64;  // area-uniform points per splat, plus the rim and the clip chord
  std::uint64_t seed = 1;
  double slack = 1e-4;              // relative to eps (and to 1 for the ellipse test), for float storage
};

// Enough surface points to hit a hole of diameter 2ε five times on average, N = ceil(5 A / (π ε²)),
// clamped to [kMinSurfacePoints, kMaxSurfacePoints].
inline constexpr std::size_t kMinSurfacePoints = 10'000, kMaxSurfacePoints = 20'000'000;
double unclamped_surface_points(double area, double eps);  // the formula, before rounding and clamping
std::size_t default_surface_points(double area, double eps);

struct SurfaceCheckReport {
  double eps = 0, slack = 0;
  std::uint64_t seed = 0;

  // (B) the surface side.
  double surface_area = 0;
  std::size_t surface_points = 0;        // checked
  double surface_points_wanted = 0;      // the default formula's value (when the count was not given)
  bool surface_points_clamped = false;   // the default count hit kMinSurfacePoints or kMaxSurfacePoints
  std::size_t uncovered_points = 0;
  double uncovered_fraction = 0;         // of the surface area: uncovered_points / surface_points
  std::size_t holes = 0;                 // clusters of uncovered points (linking distance 2.5 × spacing)
  std::size_t largest_hole_points = 0;
  double largest_hole_area = 0;          // its points × area / points
  double largest_hole_diameter = 0;      // largest distance between its points (a close lower bound)
  std::size_t hole_thinning = 1;         // > 1: holes clustered from every k-th uncovered point (memory bound)

  // (A) the splat side.
  std::size_t splats = 0, splat_points = 0;  // splat points: interior + rim + chord points checked
  double max_distance = 0;               // largest distance of a checked splat point to the surface
  std::size_t worst_splat = 0;           // the splat it belongs to
  double area_beyond_fraction = 0;       // of the total splat area, from the area-uniform interior points
  std::size_t splats_beyond = 0;         // splats with some checked point beyond ε (1 + slack)
  double largest_major = 0, diagonal = 0;  // largest major semi-axis; the surface's bounding-box diagonal
  std::size_t flipped = 0;               // no triangle within max(ε, the nearest's distance) of the centre faces its way within 60°
  std::size_t degenerate = 0;            // non-finite fields, zero axes or normal, nothing kept by the clip

  double max_distance_eps() const { return eps > 0 ? max_distance / eps : 0.0; }
  double largest_major_diagonal() const { return diagonal > 0 ? largest_major / diagonal : 0.0; }
  bool ok() const { return uncovered_points == 0 && splats_beyond == 0 && degenerate == 0; }
};

nlohmann::json to_json(const SurfaceCheckReport& report);

// Called from the calling thread with the phase and its completed fraction in [0, 1].
using SurfaceCheckProgress = std::function<void(const std::string& phase, double fraction)>;

// Which bounds a failed check broke, for one error line; with the mesh, also its float-step warning
// (core/mesh.hpp), which may be the cause.
std::string describe_failure(const SurfaceCheckReport& r, const Mesh* mesh = nullptr);

// Throws Error when eps is not finite and positive or the mesh has no area.
SurfaceCheckReport check_surface(const Mesh& mesh, const std::vector<SplatRecord>& splats, const SurfaceCheckOptions& options,
                                 const SurfaceCheckProgress& progress = {});

// The check of `splatcl splats` and `splatcl batch` on the splats about to be written: the report;
// when the run promised the two-sided bound (surface_bound) and the splats break it, Error "MODEL:
// the splats break the two-sided bound at eps E (...); nothing written" + `remedy`.
SurfaceCheckReport check_before_writing(const Mesh& mesh, const std::vector<SplatRecord>& splats, bool surface_bound, double eps,
                                        const std::string& model, const std::string& remedy, const SurfaceCheckProgress& progress = {});

}  // namespace splatcl::splats
