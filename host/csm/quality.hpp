#pragma once
// The shadow-quality study of Talpe's thesis (§6.1): the model rendered from random
// cameras on its bounding sphere, lit by a point light at a random position outside the sphere;
// every pixel's shadow test done twice, with the CSM and by exact ray casting; the result is the
// percentage of pixels whose answers differ. The thesis leaves the image size, view count, light
// distance, camera lens and denominator open; they are fixed here and reported, and both
// denominators (all image pixels, pixels showing the object) are given.
//
// Two counts of "wrong": every object pixel whose shadow answer differs (visibility), and only the
// pixels whose diffusely shaded colour differs, i.e. those facing the light (n·l > 0 with n the hit
// triangle's normal turned towards the camera): a pixel facing away is black in both renders
// whatever the shadow test says. The thesis compared rendered images (§6.1), so the second
// is its metric; the CSM's answers differ most right at the terminator, where it does not show.
#include <cstdint>

#include "csm/csm_file.hpp"
#include "csm/visibility.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"

namespace splatcl::csm {

// Stated limits (docs/reliability.md), refused before anything is allocated.
inline constexpr std::uint32_t kMaxQualityViews = 4096, kMaxQualityImage = 4096;

struct QualityOptions {
  std::uint32_t views = 16, image = 256;
  float fov_degrees = 90;  // pinhole camera looking at the sphere's centre
  // The camera's distance from the centre in sphere radii: 1 stands on the bounding sphere (Talpe
  // §6.1). A model whose surface reaches the sphere (a UV sphere, a box's corners) is then seen
  // from right beside it: one view of a UV sphere of radius 100 saw a single 1.6-unit texel of a
  // 128² map across its whole image, and that texel's silhouette answer made 51,656 of its 65,536
  // pixels wrong. 1 / sin(fov / 2) (√2 at 90°) frames the whole sphere.
  float camera_distance = 1;
  float light_max = 3;     // light distance from the centre, uniform in (1.05 R, light_max · R]
  std::uint32_t seed = 1;
  Filter filter = Filter::None;  // with PCF a pixel is lit when at least half its taps are
  float bias = 0;
};

// Throws Error naming the option (--views, --image, --fov, --camera-distance, --light-max, --bias)
// of the first value out of range: counts above the limits or zero, a field of view outside
// (0, 180) degrees, a camera inside the sphere or beyond 1e6 radii, a light not beyond the sphere,
// a non-finite bias.
void validate(const QualityOptions& options);

struct QualityReport {
  std::uint64_t pixels = 0, object_pixels = 0, wrong = 0, exact_shadowed = 0;
  std::uint64_t facing_pixels = 0, wrong_facing = 0;  // pixels with n·l > 0, and those whose answer differs
  std::uint64_t false_shadow_facing = 0;              // of wrong_facing: shadowed by the CSM, lit in truth
  double query_ms = 0;   // wall time of the CSM visibility batches (upload, kernel, read back)
  double kernel_ms = 0;  // device time of the visibility kernel (0 on the reference)
  double percent_of_image() const { return pixels ? 100.0 * static_cast<double>(wrong) / static_cast<double>(pixels) : 0; }
  double shaded_percent_of_image() const { return pixels ? 100.0 * static_cast<double>(wrong_facing) / static_cast<double>(pixels) : 0; }
  double shaded_percent_of_object() const {
    return object_pixels ? 100.0 * static_cast<double>(wrong_facing) / static_cast<double>(object_pixels) : 0;
  }
  double percent_of_object() const {
    return object_pixels ? 100.0 * static_cast<double>(wrong) / static_cast<double>(object_pixels) : 0;
  }
};

// `mesh` is the model the CSM was built from (identity object transform, else Error). CSM queries
// run on `runtime`, or on the native reference when null; primary and shadow rays on the host BVH.
QualityReport measure_quality(const Csm& csm, const Mesh& mesh, const QualityOptions& options, Runtime* runtime);
// What measure_quality needs of the CSM: built from `mesh` as loaded (identity object transform,
// require_built_from). Throws Error.
void require_quality_csm(const Csm& csm, const Mesh& mesh);

}  // namespace splatcl::csm
