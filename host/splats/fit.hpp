#pragma once
// One splat per sample (the splat thesis §2.2.2–§2.2.3, §4.1): the PCA frame with the orientation test, ring-by-ring
// growth of a circle and then an ellipse with the 2ε height test and the ±φ colour test, the size
// corrections, the accepted set Q_i and the safe points Q̄_i (Q_i without its projected convex hull).
//
// Two kernels in kernels/splat_fit.cl (splat_frames, splat_grow), driven by fit_splats(); the
// native reference of the same algorithm is in splats/reference.hpp. Both compute in float with the
// same operation order (no contraction), so on a device with correctly rounded division and square
// root the accepted and safe sets are identical.
//
// Interpretation choices where the thesis is open: the PCA uses {p_i} ∪ N_k(p_i) mean-centred; u and v take the
// sign that makes their largest component positive and n = u × v before the orientation test; the
// ellipse phase continues with the untested rest of the stopping ring plus the collected next ring,
// with b = the corrected minor axis and the violator not re-tested (switch: retest_violator, which
// uses b = d1 and re-tests it); "λ" in the size corrections is the axis ratio √λ (switch:
// literal_lambda); colour is tested before height; points on hull edges (within 1e-6 of the
// projection's extent) count as hull points.
#include <cstdint>
#include <string>
#include <vector>

#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"
#include "core/geometry.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"

namespace splatcl::splats {

inline constexpr std::uint32_t kMaxCoveredLimit = 1u << 20;
// The accepted sets' budget (entries over all splats) that sets the thesis's growth cap when none is
// given: max(kMinBudgetCap, kCoveredBudget / samples). Without it a flat face of n samples costs n²:
// a 10 x 10 x 0.05 plate at grid:1.5 (180k samples) would hold ~10^10 entries.
inline constexpr std::size_t kCoveredBudget = std::size_t{1} << 26;  // 256 MiB of uint32
inline constexpr std::uint32_t kMinBudgetCap = 128;
// The cap a budget of `budget` entries allows `samples` samples, never above `requested`.
std::uint32_t budget_growth_cap(std::size_t samples, std::uint32_t requested, std::size_t budget = kCoveredBudget);

struct FitOptions {
  float eps = 0;                 // ε, absolute, in model units
  int color_tolerance = 255;     // φ per channel, 0..255; 255 ignores colour
  bool literal_lambda = false;   // read "λ" in the size corrections literally instead of as √λ
  bool retest_violator = false;  // ellipse phase with b = d1 and the circle's violator re-tested
  // Clipped splats (the splat thesis §4.2.2, a proposal it left untried): a violator within
  // 90° of the mean direction to the earlier skipped violators is skipped instead of ending the
  // phase; the splat is then cut by a line perpendicular to that mean direction, halfway between the
  // farthest accepted and the nearest skipped sample along it.
  bool clip = false;
  // Growth cap (an extension; the thesis grows without bound): a splat stops
  // accepting samples when Q holds this many, as if no violator had been met. It keeps growth and
  // selection linear in the sample count on flat regions, where one splat would otherwise walk the
  // whole plane; the surface bound and gap filling (splats/surface_fit.hpp) keep the cover whole.
  std::uint32_t max_covered = kMaxCoveredLimit;  // the two-sided setup (pipeline_options) uses 128
  // Size at the accepted samples (an extension for the two-sided bound): each axis ends at the
  // farthest accepted sample (d1, λ1) instead of the thesis's size corrections, which reach the
  // violator (d2, λ2, or beyond for colour) - a point that by definition lies more than ε off the
  // splat's plane, so nearly every corrected splat leaves the surface at its rim.
  bool size_at_accepted = false;
  // Crease-aware frames (an extension): a sample's PCA frame takes only the neighbours whose normal
  // lies within this angle of its own, so that splats on a sharp edge (a box's, a CAD part's) lie in
  // one face's plane instead of bevelling it; 180 takes every neighbour, as the thesis does.
  // Surfaces whose normals turn less than this between neighbouring samples get the thesis's frames
  // bit for bit.
  float crease_degrees = 180.0f;
  // Growth kernel shape (design.md): Cpu = a few workers each growing blocks of consecutive splats
  // with scratch kept warm in its cache; Gpu = one work-item per splat. Auto picks by device type.
  // Both give the same splats.
  Shape shape = Shape::Auto;
};

// Throws Error for ε not positive and finite, φ outside 0..255, or max_covered outside 4..kMaxCoveredLimit.
void validate(const FitOptions& options);

// Unit axes of a sample's splat: major u, minor v, normal n.
struct Frame {
  Vec4 u, v, n;
};

// What ended a growth phase.
enum class Stop : std::uint32_t { None = 0, Geometry = 1, Color = 2 };

// One grown splat. major and minor are the semi-axis vectors (w = their length); center.w is the
// circle phase's Stop and normal.w the ellipse phase's, as floats.
struct SplatShape {
  Vec4 center, normal, major, minor;
};

// Compressed rows: row i = items[offsets[i], offsets[i + 1]).
struct Rows {
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::uint32_t> items;
  std::size_t size() const { return offsets.size() - 1; }
  std::size_t row_size(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  const std::uint32_t* begin(std::size_t i) const { return items.data() + offsets[i]; }
  const std::uint32_t* end(std::size_t i) const { return items.data() + offsets[i + 1]; }
};

// FitOptions::crease_degrees as the frames' cosine threshold (-2 for 180: every neighbour).
float crease_cosine(float crease_degrees);

struct FitResult {
  std::vector<Frame> frames;
  std::vector<SplatShape> splats;  // splat i started at sample i
  Rows covered;                    // Q_i in acceptance order, start point first
  Rows safe;                       // Q̄_i, same order, start point first
  // Per splat: unit clip direction in the splat's (u, v) frame and the clip line's distance from
  // the centre along it; offset +inf (and direction 0) when the splat is not clipped.
  std::vector<Vec4> clips;
};

// Device timings of the fit kernels (ms) and how often the growth had to be relaunched with more
// scratch because a splat outgrew it.
struct FitTimings {
  double frames_ms = 0, grow_ms = 0, transfer_ms = 0;
  unsigned relaunches = 0;
};

// Runs both kernels on `runtime`'s device. With `frames` given, the growth uses them instead of
// the frames kernel (tests feed both implementations the same frames). A profiler collects the
// kernel events ("splat frames", "splat grow").
FitResult fit_splats(Runtime& runtime, const Samples& samples, const Neighborhoods& neighbors, const FitOptions& options,
                     const std::vector<Frame>* frames = nullptr, FitTimings* timings = nullptr,
                     Profiler* profiler = nullptr);

// Fills covered and safe from per-splat sets whose hull points carry kOnHullBit.
void set_rows(const std::vector<std::vector<std::uint32_t>>& sets, FitResult& result);

// The bit that marks a hull point in the growth kernel's output (sample counts stay below 2^31).
inline constexpr std::uint32_t kOnHullBit = 0x80000000u;

}  // namespace splatcl::splats
