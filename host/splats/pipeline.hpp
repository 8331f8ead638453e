#pragma once
// The whole splat stage on one mesh: sample → kNN → fit and grow one splat per sample (OpenCL, or
// the native reference) → greedy selection → optimisation → error metrics, timed per phase; and
// the independent check behind `splatcl splats verify`.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/runtime.hpp"
#include "splats/fit.hpp"
#include "core/mesh.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"
#include "splats/selection.hpp"
#include "splats/splat_file.hpp"
#include "splats/surface_fit.hpp"

namespace splatcl::splats {

// The splat method's version: raised when generate_splats makes other splats from the same mesh
// and options, so that cached splats (the presenter's asset cache, `splatcl batch`'s reuse) are
// rebuilt rather than reused. 2: the gap filling's check-and-fill rounds went from 6 to 10.
// 3: the bound leaves room for float rounding far from the origin, gap-search cells are cut across
// needles, and samples on a non-planar polygon's fan triangles keep their normals near the
// triangle's. 4: growth passes over samples on the other side of a thin part (splat_other_sheet),
// frames are oriented by the neighbours on their side of a crease, and with the colour variant
// every splat keeps to its colour (fill_gaps). 5: polygons whose fan triangles stand more than 30°
// off their normal are loaded as their fan (core/mesh.cpp), so their samples take the triangles'
// normals. 6: the thesis's method (thesis_only) caps growth at kCoveredBudget / samples when no cap is
// given, so that flat faces stay linear; a UTF-8 byte-order mark no longer shifts an OBJ's indices;
// an inside-out closed part that lies inside no other is turned outward (core/mesh.cpp). 7: gap
// splats also try major axes along their triangle's other edges (fewer of them along the borders
// of non-square faces). 8: the kNN graph passes over samples on an opposed sheet (a thin plate's
// other side; splats/neighbors.hpp), and the surface bound shrinks a long grown splat from 4:1
// instead of whole (needles). 9: the surface bound counts only triangles that face within 60° of
// the splat (fins: a strip of a hole's wall laid along the rim over the plate's top). 11: a texture
// coordinate of exactly 1 takes the last texel, not the first (colours along u = 1 / v = 1 seams).
// 12: a polygon with no Newell normal whose fan has area (a bowtie) is split into its fan instead
// of kept as a zero-area face.
inline constexpr int kSplatMethodVersion = 12;

struct PipelineOptions {
  SamplingOptions sampling;
  unsigned k = 10;
  FitOptions fit;
  unsigned rounds = 5;  // relaxation + removal rounds
  // The two-sided bound (splats/surface_fit.hpp): grown splats bounded by the surface, zero-size
  // splats left out, gaps filled. Off: the thesis's method alone.
  bool surface_bound = false;
  // Non-zero: fit.max_covered is lowered to budget_growth_cap(samples, ..., covered_budget) once the
  // samples are known (the thesis's method without a given cap: its sets' memory is what is bounded).
  std::size_t covered_budget = 0;
};

struct PhaseTime {
  std::string phase;
  double ms = 0;
};

struct SplatRun {
  Samples samples;
  Neighborhoods neighbors;
  FitResult fit;
  std::vector<std::uint32_t> selected;  // increasing splat (= start sample) index
  std::size_t greedy_count = 0;         // splats after the greedy cover, before optimisation
  OptimiseStats optimise;
  ErrorStats before, after;             // over all splats / over the selected ones (Q̄ relation)
  std::vector<SplatRecord> kept_splats;  // the selected splats as certified against the surface (surface_bound)
  std::vector<SplatRecord> gap_splats;   // added where the surface was not covered (surface_bound)
  bool surface_bound = false;
  std::size_t degenerate_dropped = 0;   // selected splats of zero size left out of the output (surface_bound)
  SurfaceFitStats surface_fit;
  // Coordinates far from 1 are processed as origin + scale · x with x of diagonal 1; the samples,
  // fit and gap splats are in those units, records() in the mesh's own.
  DVec3 origin;
  double scale = 1;
  std::vector<PhaseTime> phases;
  FitTimings fit_timings;
  std::uint32_t max_covered = 0;        // the growth cap the fit ran with
  std::string fit_backend;              // device name, or "reference"

  double total_ms() const;
  std::size_t output_count() const { return surface_bound ? kept_splats.size() + gap_splats.size() : selected.size(); }
  std::vector<SplatRecord> records() const;
};

// How far writing a splat of a mesh within `box` as floats may move its points (centre and axes
// rounded): the surface bound is fitted to ε less this. The same from the box's reach (largest
// |coordinate|) and diagonal.
double float_rounding(const Box& box);
double float_rounding(double reach, double diagonal);

// Called with the name of each phase as it starts (for progress display).
using Progress = std::function<void(const std::string& phase)>;

// runtime == nullptr runs the native reference fit. Throws Error for bad options or input.
SplatRun generate_splats(const Mesh& mesh, const ColorSource& colors, const PipelineOptions& options, Runtime* runtime,
                         const Progress& progress = {});

// Counts, reduction, errors against ε, phase times.
nlohmann::json run_statistics(const SplatRun& run, const PipelineOptions& options);

// Independent check of a splat set against the samples: a sample is covered by a splat when its
// projection lies inside the ellipse (and on the kept side of its clip line) and its distance to the splat plane is at most ε (both with a
// relative slack of 1e-4 for float storage); every sample must be covered and every splat must
// cover at least one sample (its start point, which lies within ε of it by construction).
struct VerifyReport {
  std::size_t samples = 0, uncovered = 0, splats = 0, empty_splats = 0;
  double mean_error = 0, max_error = 0;  // distance to the nearest covering splat, over covered samples
  bool ok() const { return uncovered == 0 && empty_splats == 0; }
};
VerifyReport verify_splats(const Samples& samples, const std::vector<SplatRecord>& splats, float eps);

}  // namespace splatcl::splats
