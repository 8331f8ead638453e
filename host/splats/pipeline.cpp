#include "splats/pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include <flann/flann.hpp>

#include "math/dvec3.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "core/parallel.hpp"
#include "splats/reference.hpp"

namespace splatcl::splats {

double SplatRun::total_ms() const {
  double total = 0;
  for (const auto& p : phases) total += p.ms;
  return total;
}

namespace {

bool degenerate(const SplatShape& s) { return !(s.major.w > 0 && s.minor.w > 0); }

// Grown splat j as written: its shape, clip line and start sample's colour.
SplatRecord grown_record(const FitResult& fit, const Samples& samples, std::uint32_t j) {
  const SplatShape& s = fit.splats[j];
  const Vec4& clip = fit.clips[j];
  return {xyz(s.center), xyz(s.normal), xyz(s.major), xyz(s.minor), samples.colors[j], clip.x, clip.y, clip.z};
}

// Meshes whose coordinates are far from 1 are processed in units of their diagonal; so is a mesh far
// from the origin for its size (a scan in georeferenced coordinates): its float samples would carry
// steps of its distance's precision into the fit.
bool needs_normalising(const Box& box) {
  const double diagonal = box.diagonal(), reach = box.reach();
  return !(diagonal >= 1e-6 && diagonal <= 1e6 && reach <= 1e6 && reach <= 100 * diagonal);
}

// The samples' spacing: the grid's, else (vertices alone) the median distance to the nearest neighbour.
double sample_spacing(const SplatRun& run) {
  if (run.samples.grid_spacing > 0) return run.samples.grid_spacing;
  const Neighborhoods& nb = run.neighbors;
  if (nb.k == 0 || run.samples.size() == 0) return 0;
  std::vector<float> nearest(run.samples.size());
  for (std::size_t i = 0; i < nearest.size(); ++i) nearest[i] = length(xyz(run.samples.positions[i]) - xyz(run.samples.positions[nb.row(i)[0]]));
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace

double float_rounding(const Box& box) { return float_rounding(box.reach(), box.exact_diagonal()); }

double float_rounding(double reach, double diagonal) {
  // Each coordinate of a splat's centre (within the box) and of its two axes (each shorter than the
  // diagonal) rounds by at most 2^-24 of its magnitude when written.
  // In double throughout: twice a float diagonal of 1.7e38 overflowed float (every eps was refused).
  return std::sqrt(3.0) * std::ldexp(reach + 2 * diagonal, -24);
}

std::vector<SplatRecord> SplatRun::records() const {
  std::vector<SplatRecord> out;
  if (surface_bound) {
    out = kept_splats;
  } else {
    out.reserve(selected.size());
    for (const std::uint32_t j : selected) out.push_back(grown_record(fit, samples, j));
  }
  out.insert(out.end(), gap_splats.begin(), gap_splats.end());
  if (scale != 1 || origin.x != 0 || origin.y != 0 || origin.z != 0) {
    for (SplatRecord& r : out) {
      r.center = to_float(origin + scale * DVec3(r.center));
      r.major = to_float(scale * DVec3(r.major));
      r.minor = to_float(scale * DVec3(r.minor));
      r.clip_offset = static_cast<float>(scale * r.clip_offset);
    }
  }
  return out;
}

SplatRun generate_splats(const Mesh& input_mesh, const ColorSource& input_colors, const PipelineOptions& input_options,
                         Runtime* runtime, const Progress& progress) {
  validate(input_options.fit);
  if (input_options.k == 0) throw Error("--k must be at least 1");
  SplatRun run;
  // Huge or tiny coordinates: work in units of the diagonal so that squared distances, ε and the
  // float samples keep their precision; records() maps the result back.
  const Box input_box = input_mesh.bounds();
  Mesh normalised_mesh;
  ColorSource normalised_colors;
  PipelineOptions normalised_options;
  const bool normalise = needs_normalising(input_box);
  if (normalise) {
    const double diagonal = input_box.exact_diagonal();
    if (!(diagonal > 0 && std::isfinite(diagonal)))
      throw Error(input_mesh.source + ": the mesh has no extent (all vertices coincide) or an extent beyond double range");
    run.origin = 0.5 * (DVec3(input_box.lo) + DVec3(input_box.hi));
    run.scale = diagonal;
    normalised_mesh = input_mesh;
    for (Vec3& v : normalised_mesh.vertices) v = to_float((1.0 / run.scale) * (DVec3(v) - run.origin));
    normalised_colors = input_colors;
    normalised_colors.bounds = normalised_mesh.bounds();
    normalised_options = input_options;
    normalised_options.fit.eps = static_cast<float>(input_options.fit.eps / run.scale);
    if (normalised_options.sampling.spacing > 0) normalised_options.sampling.spacing /= run.scale;
    validate(normalised_options.fit);
  }
  // The bound the splats are fitted to: ε less what writing them as floats may move them (a sphere
  // of radius 100 at 1e6, ε 0.35, loses 0.30 ε; one at the origin nothing measurable), so the written splats
  // keep ε against the mesh as read; where that takes most of ε, the float output cannot keep it.
  const double rounding = float_rounding(input_box);
  if (input_options.surface_bound && !(rounding <= 0.5 * input_options.fit.eps))
    throw Error(fmt::format("{}: coordinates reach {:.7g}, where the float splat file's steps move a splat by up to {:.3g}, more than "
                            "half of eps {:.3g}: translate the mesh nearer the origin (a scene object: give it a fit) or raise eps (--eps, "
                            "--eps-diag; a scene's quality.eps_diagonal)",
                            input_mesh.source, input_box.reach(), rounding, input_options.fit.eps));
  const auto bound_eps = static_cast<float>((input_options.fit.eps - rounding) / (normalise ? run.scale : 1.0));
  const Mesh& mesh = normalise ? normalised_mesh : input_mesh;
  const ColorSource& colors = normalise ? normalised_colors : input_colors;
  const PipelineOptions& options = normalise ? normalised_options : input_options;
  auto phase = [&](const std::string& name, auto&& work) {
    if (progress) progress(name);
    Stopwatch clock;
    work();
    run.phases.push_back({name, clock.elapsed_ms()});
  };
  run.surface_bound = options.surface_bound;
  SamplingOptions sampling = options.sampling;
  if (sampling.mode == SampleMode::Spacing && sampling.spacing == 0) {
    sampling.spacing = auto_spacing(options.fit.eps, mesh.bounds().diagonal());
    sampling.coarsen = true;
  }
  phase("sampling", [&] { run.samples = sample_mesh(mesh, sampling, colors); });
  phase("knn", [&] { run.neighbors = find_neighbors(run.samples.positions, options.k, &run.samples.normals, crease_cosine(options.fit.crease_degrees));
  });
  FitOptions growth = options.fit;
  if (options.surface_bound) growth.eps = growth_eps(options.fit.eps);
  if (options.covered_budget > 0)
    growth.max_covered = budget_growth_cap(run.samples.size(), growth.max_covered, options.covered_budget);
  run.max_covered = growth.max_covered;
  if (runtime) {
    run.fit_backend = runtime->info().name;
    // Frames and growth are separate kernels; their device times split the fit phase.
    Stopwatch clock;
    if (progress) progress("fit");
    run.fit = fit_splats(*runtime, run.samples, run.neighbors, growth, nullptr, &run.fit_timings);
    const double wall = clock.elapsed_ms();
    run.phases.push_back({"pca", run.fit_timings.frames_ms});
    run.phases.push_back({"growth+safe", std::max(0.0, wall - run.fit_timings.frames_ms)});
  } else {
    run.fit_backend = "reference";
    std::vector<Frame> frames;
    phase("pca", [&] { frames = reference::fit_frames(run.samples, run.neighbors, growth.crease_degrees); });
    phase("growth+safe", [&] { run.fit = reference::grow_splats(run.samples, run.neighbors, frames, growth); });
  }
  std::optional<Surface> surface;
  if (options.surface_bound) {
    phase("surface", [&] { surface.emplace(mesh); });
    phase("surface bound", [&] { bound_by_surface(*surface, run.samples, run.neighbors, run.fit, bound_eps, run.surface_fit); });
  }
  Rows inverse;
  phase("inverse", [&] { inverse = inverse_index(run.fit.safe, run.samples.size()); });
  phase("selection", [&] {
    run.selected = greedy_cover(run.fit.safe, inverse, run.neighbors.weight);
    run.greedy_count = run.selected.size();
  });
  phase("optimisation", [&] {
    run.selected = optimise_selection(std::move(run.selected), run.fit.safe, inverse, run.neighbors.weight, run.neighbors,
                                      options.rounds, &run.optimise);
  });
  if (options.surface_bound) {
    phase("gap fill", [&] {
      std::vector<SplatRecord> kept;
      for (const std::uint32_t j : run.selected) {
        if (degenerate(run.fit.splats[j]))
          ++run.degenerate_dropped;
        else
          kept.push_back(grown_record(run.fit, run.samples, j));
      }
      run.gap_splats = fill_gaps(*surface, mesh, colors, {options.fit.color_tolerance, 0.5 * sample_spacing(run)}, kept,
                                 bound_eps, run.surface_fit, progress);
      run.kept_splats = std::move(kept);
    });
  }
  phase("metrics", [&] {
    std::vector<std::uint8_t> chosen(run.samples.size(), 0);
    for (const std::uint32_t j : run.selected) chosen[j] = 1;
    run.before = coverage_errors(run.samples, run.fit.splats, inverse, nullptr);
    run.after = coverage_errors(run.samples, run.fit.splats, inverse, &chosen);
    // In the mesh's own units, as ε is reported (a sphere scaled by 1e4 at 1e6, processed in units
    // of its diagonal, reported a mean error of 1.2e-5 ε; an L-bracket scaled by 1e-5 one of 10,860 ε).
    for (ErrorStats* e : {&run.before, &run.after}) e->mean *= run.scale, e->max *= run.scale;
  });
  if (run.after.uncovered != 0 && !options.surface_bound)
    throw Error(fmt::format("splat selection left {} samples uncovered", run.after.uncovered));
  return run;
}

nlohmann::json run_statistics(const SplatRun& run, const PipelineOptions& options) {
  const double eps = options.fit.eps;
  const double n = static_cast<double>(run.samples.size()), m = static_cast<double>(run.selected.size());
  auto errors = [&](const ErrorStats& e) {
    return nlohmann::json{{"mean", e.mean}, {"max", e.max}, {"mean_over_eps", e.mean / eps}, {"max_over_eps", e.max / eps},
                          {"mean_color_error", {e.color[0], e.color[1], e.color[2]}}};
  };
  // Splats whose clip line cuts them as written: the surface fit shrinks clipped splats afterwards,
  // and most of an octahedron's lines then cut nothing at scale 1 (a helper's audit: 459 counted,
  // 98 cutting). Such lines stay in the file: drawn larger (the presenter's k), they may cut.
  std::size_t largest = 0, clipped = 0;
  for (const SplatRecord& r : run.records()) clipped += clip_cuts(r) ? 1 : 0;
  for (std::size_t j = 0; j < run.fit.covered.size(); ++j) largest = std::max(largest, run.fit.covered.row_size(j));
  nlohmann::json phases = nlohmann::json::object();
  for (const auto& p : run.phases) phases[p.phase] = p.ms;
  return {{"samples", run.samples.size()},
          {"vertex_samples", run.samples.vertex_samples},
          {"duplicate_samples_dropped", run.samples.duplicates_dropped},
          {"grid_spacing", run.samples.grid_spacing},
          {"sampling", to_string(options.sampling)},
          {"k", run.neighbors.k},
          {"eps", eps},
          {"color_tolerance", options.fit.color_tolerance},
          {"literal_lambda", options.fit.literal_lambda},
          {"retest_violator", options.fit.retest_violator},
          {"clip", options.fit.clip},
          {"crease_angle", options.fit.crease_degrees},
          {"size_at_accepted", options.fit.size_at_accepted},
          {"clipped_splats", clipped},
          {"surface_bound", run.surface_bound},
          {"max_covered", run.max_covered},
          {"sampling_note", run.samples.note},
          {"surface_fit", {{"shrunk_splats", run.surface_fit.shrunk},
                           {"gap_splats", run.gap_splats.size()},
                           {"gap_rounds", run.surface_fit.gap_rounds},
                           {"cells_checked", run.surface_fit.cells_checked},
                           {"uncovered_cells", run.surface_fit.uncovered_cells},
                           {"degenerate_dropped", run.degenerate_dropped},
                           {"recertified_splats", run.surface_fit.recertified},
                           {"certify_ms", run.surface_fit.certify_ms},
                           {"gap_search_ms", run.surface_fit.gap_search_ms},
                           {"normalised_scale", run.scale}}},
          {"output_splats", run.output_count()},
          {"splats_greedy", run.greedy_count},
          {"splats", run.output_count()},
          {"splats_selected", run.selected.size()},
          {"samples_per_splat", m > 0 ? n / m : 0.0},
          {"splats_percent_of_samples", n > 0 ? 100.0 * m / n : 0.0},
          {"optimisation", {{"rounds", run.optimise.rounds}, {"swaps", run.optimise.swaps}, {"removals", run.optimise.removals}}},
          {"mean_covered_per_splat", n > 0 ? static_cast<double>(run.fit.covered.items.size()) / n : 0.0},
          {"largest_covered_set", largest},
          {"error_before_selection", errors(run.before)},
          {"error_after_selection", errors(run.after)},
          {"fit_backend", run.fit_backend},
          {"fit_relaunches", run.fit_timings.relaunches},
          {"phase_ms", phases},
          {"total_ms", run.total_ms()}};
}

VerifyReport verify_splats(const Samples& samples, const std::vector<SplatRecord>& splats, float eps) {
  VerifyReport report;
  report.samples = samples.size();
  report.splats = splats.size();
  const double slack = 1e-4;
  const double height_limit = static_cast<double>(eps) * (1 + slack);
  std::vector<std::vector<std::pair<std::uint32_t, double>>> covered(splats.size());
  if (samples.size() > 0) {
    flann::Matrix<float> data(const_cast<float*>(&samples.positions[0].x), samples.size(), 3, sizeof(Vec4));
    flann::Index<flann::L2_Simple<float>> index(data, flann::KDTreeSingleIndexParams(10));
    index.buildIndex();
    parallel_for(splats.size(), 64, [&](std::size_t j, std::size_t) {
      const SplatRecord& s = splats[j];
      const double a = length(DVec3(s.major)), b = length(DVec3(s.minor));
      if (!(a > 0 && b > 0) || !finite(s.center)) return;
      const Vec3 u = to_float(normalized(DVec3(s.major))), v = to_float(normalized(DVec3(s.minor))),
                 nrm = to_float(normalized(DVec3(s.normal)));
      const float reach = static_cast<float>(std::sqrt(a * a + height_limit * height_limit) * (1 + slack));
      std::vector<std::vector<std::size_t>> ids;
      std::vector<std::vector<float>> distances;
      float query[3] = {s.center.x, s.center.y, s.center.z};
      flann::Matrix<float> q(query, 1, 3);
      flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);
      index.radiusSearch(q, ids, distances, reach * reach, params);
      for (const std::size_t m : ids[0]) {
        const Vec4& p = samples.positions[m];
        const double dx = double{p.x} - s.center.x, dy = double{p.y} - s.center.y, dz = double{p.z} - s.center.z;
        const double x = u.x * dx + u.y * dy + u.z * dz, y = v.x * dx + v.y * dy + v.z * dz;
        const double h = std::fabs(nrm.x * dx + nrm.y * dy + nrm.z * dz);
        const bool kept_by_clip = !std::isfinite(s.clip_offset) || x * s.clip_x + y * s.clip_y <= s.clip_offset + slack * std::max(a, b);
        if (x * x / (a * a) + y * y / (b * b) <= 1 + slack && h <= height_limit && kept_by_clip)
          covered[j].emplace_back(static_cast<std::uint32_t>(m), h);
      }
    });
  }
  std::vector<double> nearest(samples.size(), INFINITY);
  for (const auto& list : covered) {
    if (list.empty()) ++report.empty_splats;
    for (const auto& [m, h] : list) nearest[m] = std::min(nearest[m], h);
  }
  double sum = 0;
  for (const double h : nearest) {
    if (!std::isfinite(h)) {
      ++report.uncovered;
      continue;
    }
    sum += h;
    report.max_error = std::max(report.max_error, h);
  }
  const std::size_t counted = report.samples - report.uncovered;
  report.mean_error = counted ? sum / static_cast<double>(counted) : 0.0;
  return report;
}

}  // namespace splatcl::splats
