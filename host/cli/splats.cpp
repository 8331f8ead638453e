// splatcl splats: mesh → elliptical splats (sampling, kNN, per-sample fit and growth on the OpenCL
// device, greedy selection, optimisation) → PLY and statistics JSON; `splatcl splats verify` checks
// a splat file against its model.
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "io/json_keys.hpp"
#include "cli/parameter_options.hpp"
#include "cli/model_input.hpp"
#include "cli/progress.hpp"
#include "io/atomic_file.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"
#include "splats/gaussian_file.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/render.hpp"
#include "splats/surface_check.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::splats;

struct SplatsOptions {
  DeviceOptions device;
  std::string model, output, stats, render;
  std::string format = "splatcl";  // of -o: "splatcl" (splat PLY) or "3dgs" (3D Gaussian Splatting PLY)
  bool reference = false;
  bool strict = false;  // mesh problems (mesh.hpp: MeshProblems) are an error, not a warning
  bool no_check = false;  // skip the end-of-run surface check
  std::shared_ptr<GivenParameters> given = std::make_shared<GivenParameters>();  // the build parameters given
};

struct VerifyOptions {
  std::string model, splats, json;
  std::string eps, points, ellipse_points, seed;  // as given ("" when not); parsed and validated by run_verify
  bool keep_winding = false;  // as splatcl splats --keep-winding: the splats were made from the faces as wound
};


int run_splats(const SplatsOptions& o) {
  if (o.model.empty()) throw Error("splats: a MODEL is required (see splatcl splats --help)");
  if (o.output.empty()) throw Error("splats: an output file is required (-o OUT.ply)");
  if (o.format != "splatcl" && o.format != "3dgs") throw Error("--format must be splatcl or 3dgs, not '" + o.format + "'");
  // Every output must be writable before any work; all are staged and committed together at the
  // end, so a late failure (stats, render) leaves none of them, -o included.
  check_output_file(o.output, "-o");
  check_output_file(o.stats, "--stats");
  check_output_file(o.render, "--render");
  check_distinct_outputs({{"-o", o.output}, {"--stats", o.stats}, {"--render", o.render}});
  check_outputs_spare_inputs({{"-o", o.output}, {"--stats", o.stats}, {"--render", o.render}}, {{"model", o.model}});
  check_output_extension(o.output, "-o", {".ply"}, "a PLY of splats");
  check_output_extension(o.render, "--render", {".png", ".exr"}, "the picture");  // not after the work
  // The same parameters, parsing and translation as `splatcl batch` (splats/pipeline_options.hpp).
  SplatParameters params;
  for (const auto& [option, value] : *o.given) set_parameter(params, option, value);
  validate(params, Spelling::Option);
  ProgressLine progress("splats");
  Stopwatch load_clock;
  // About the centre of its box where floats are too coarse there for its size or eps (the file records the origin).
  const Mesh mesh = load_model(o.model, progress, winding(params), o.strict, {ModelOrigin::CentreWhen, recentre_test(params)});
  const double load_ms = load_clock.elapsed_ms();
  const SplatSetup setup = splat_setup(params, mesh, o.model);
  const PipelineOptions& options = setup.options;
  const ColorSource& colors = setup.colors;
  const double diagonal = setup.diagonal;
  const std::string& color_description = setup.color_description;
  std::shared_ptr<Runtime> runtime;
  if (!o.reference) runtime = Runtime::create(o.device.device);
  const auto show_phase = [&](const std::string& phase) { progress.show(phase); };
  SplatRun run = generate_splats(mesh, colors, options, runtime.get(), show_phase);
  run.phases.insert(run.phases.begin(), {"load", load_ms});
  const std::vector<SplatRecord> records = run.records();
  // The same check as `splatcl splats verify`, on the splats as they will be written.
  std::optional<SurfaceCheckReport> check;
  if (!o.no_check) {
    Stopwatch check_clock;
    check = check_before_writing(mesh, records, run.surface_bound, options.fit.eps, o.model, " (--no-check writes them unchecked)",
                                 [&](const std::string& phase, double fraction) {
                                   progress.show(fmt::format("checking: {} {:.0f}%", phase, 100 * fraction));
                                 });
    run.phases.push_back({"check", check_clock.elapsed_ms()});
  }
  // Commit order: the secondary outputs first, -o last.
  StagedOutputs outputs;
  if (!o.stats.empty()) outputs.stage(o.stats);
  if (!o.render.empty()) outputs.stage(o.render);
  outputs.stage(o.output);
  progress.show("writing " + o.output);
  Stopwatch write_clock;
  std::size_t unclipped = 0;
  outputs.write(o.output, [&](const std::string& path) {
    if (o.format == "3dgs")
      unclipped = write_gaussian_file(path, records, mesh.origin);
    else
      write_splat_file(path, records, splat_file_info(setup, run, o.model));
  });
  run.phases.push_back({"write", write_clock.elapsed_ms()});
  nlohmann::json stats = splat_statistics(run, setup, o.model, o.output);
  if (check) stats["surface_check"] = to_json(*check);
  if (!o.stats.empty()) outputs.write(o.stats, [&](const std::string& path) { write_file_atomically(path, json_text(stats) + "\n"); });
  if (!o.render.empty()) {
    progress.show("rendering " + o.render);
    splats::RenderOptions view;
    view.random_colors = colors.field == ColorField::Grey && !colors.texture;
    outputs.write(o.render, [&](const std::string& path) { render_splats(path, records, view); });
  }
  outputs.commit();
  progress.clear();
  if (unclipped > 0)
    std::fprintf(stderr, "splatcl: warning: %zu of %zu splats are clipped; 3DGS has no clip lines, so %s has them unclipped\n",
                 unclipped, records.size(), printable(o.output).c_str());

  const double n = static_cast<double>(run.samples.size()), m = static_cast<double>(run.selected.size());
  fmt::print("model      {} ({} vertices, {} faces, bbox diagonal {:.6g})\n", o.model, mesh.vertices.size(), mesh.face_count(), diagonal);
  fmt::print("samples    {} ({}; {} duplicates dropped), k = {}\n", run.samples.size(), to_string(options.sampling),
             run.samples.duplicates_dropped, run.neighbors.k);
  fmt::print("eps        {:.6g} ({:.3g} of the diagonal{}), colour tolerance {} ({})\n", options.fit.eps, options.fit.eps / diagonal,
             setup.eps_capped ? fmt::format("; {:.6g} asked, capped at the diagonal", setup.requested_eps) : "",
             options.fit.color_tolerance, color_description);
  if (!run.samples.note.empty()) fmt::print(stderr, "splatcl: note: {}: {}\n", o.model, run.samples.note);
  // With none selected (every written splat a gap splat, as on sheets thinner than the sample
  // spacing) there is no per-splat ratio to print.
  const std::string ratio = m > 0 ? fmt::format("{:.1f}% of the samples, {:.2f} samples per splat", 100.0 * m / n, n / m)
                                  : fmt::format("none of the {} samples", run.samples.size());
  fmt::print("splats     {} selected ({}); greedy {}, then {} swaps and {} removals in {} rounds\n", run.selected.size(), ratio,
             run.greedy_count, run.optimise.swaps, run.optimise.removals, run.optimise.rounds);
  if (run.surface_bound)
    fmt::print("surface    {} grown splats shrunk to the surface, {} of the selected made smaller by certification, {} added "
               "in {} gap rounds; {} written\n",
               run.surface_fit.shrunk, run.surface_fit.recertified, run.gap_splats.size(), run.surface_fit.gap_rounds,
               run.output_count());
  fmt::print("error      before selection mean {:.3g} ({:.1f}% of eps); after mean {:.3g} ({:.1f}%), max {:.3g} ({:.1f}%)\n",
             run.before.mean, 100 * run.before.mean / options.fit.eps, run.after.mean, 100 * run.after.mean / options.fit.eps,
             run.after.max, 100 * run.after.max / options.fit.eps);
  std::string timing = "time      ";
  for (const auto& p : run.phases) timing += fmt::format(" {} {:.0f} ms,", p.phase, p.ms);
  timing.pop_back();
  fmt::print("{}; total {:.2f} s (fit on {})\n", timing, run.total_ms() / 1000.0, run.fit_backend);
  if (check)
    fmt::print("check      {}: {:.3g}% of the surface uncovered, splats up to {:.3g} eps from it, {} beyond eps ({} surface points, "
               "{} splat points)\n",
               check->ok() ? "two-sided bound holds" : "two-sided bound BROKEN (the thesis's method alone does not keep it)",
               100 * check->uncovered_fraction, check->max_distance_eps(), check->splats_beyond, check->surface_points,
               check->splat_points);
  fmt::print("wrote      {}{}{}\n", o.output, o.stats.empty() ? "" : ", " + o.stats, o.render.empty() ? "" : ", " + o.render);
  return 0;
}

// A whole-string number for option `what`, or Error naming it.
double parse_number(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw Error(what + " must be a number, not '" + text + "'");
  return value;
}

std::uint64_t parse_count(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  unsigned long long value = 0;
  try {
    if (!text.empty() && text[0] != '-' && text[0] != '+') value = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw Error(what + " must be a non-negative integer, not '" + text + "'");
  return value;
}

// Why a mesh may not be the one the splats were built from, by where it lies in its file's
// coordinates (Mesh::file_lo, file_hi, whatever origin it was read about): its box is centred away
// from the splats' origin by more than its diagonal (a file built far out, checked against the mesh
// moved to the origin by hand), or the file records origin 0 for a mesh whose floats are coarse,
// which splats reads about its centre (a file of an older version, or of another mesh). Empty
// otherwise.
std::string origin_mismatch(const DVec3& origin, const Mesh& mesh) {
  const DVec3 centre = 0.5 * mesh.file_lo + 0.5 * mesh.file_hi;
  const double diagonal = mesh.file_diagonal(), away = length(centre - origin);
  const bool at_zero = origin.x == 0 && origin.y == 0 && origin.z == 0;
  if (!at_zero && away > diagonal)
    return fmt::format("the splats' positions are relative to origin ({:.12g}, {:.12g}, {:.12g}) (their file's splatcl_origin), and "
                       "this mesh's box is centred {:.6g} from it, more than its {:.4g} diagonal: is it the mesh they were built from?",
                       origin.x, origin.y, origin.z, away, diagonal);
  if (at_zero && coarse_for_floats(mesh.file_reach(), diagonal))
    return "the splat file records origin 0, but this mesh's coordinates are coarse as floats for its size, and splatcl splats reads "
           "such a mesh about its centre and records that origin: the splats come from another mesh, or from splatcl before "
           "splat file version 4";
  return {};
}

int run_verify(const VerifyOptions& o) {
  SurfaceCheckOptions check;
  if (!o.eps.empty()) {
    check.eps = parse_number(o.eps, "--eps");
    if (!(check.eps > 0) || !(check.eps <= std::numeric_limits<float>::max()))
      throw Error("--eps must be positive and within float range (< 3.4e38), not " + o.eps);
  }
  if (!o.points.empty()) {
    check.surface_points = parse_count(o.points, "--points");
    if (check.surface_points < 1000 || check.surface_points > kMaxSurfacePoints)
      throw Error(fmt::format("--points must be 1000 to {}, not {}", kMaxSurfacePoints, o.points));
  }
  if (!o.ellipse_points.empty()) {
    check.ellipse_points = parse_count(o.ellipse_points, "--ellipse-points");
    if (check.ellipse_points < 1 || check.ellipse_points > 100'000)
      throw Error("--ellipse-points must be 1 to 100000, not " + o.ellipse_points);
  }
  if (!o.seed.empty()) check.seed = parse_count(o.seed, "--seed");
  check_output_file(o.json, "--json");
  check_outputs_spare_inputs({{"--json", o.json}}, {{"mesh", o.model}, {"splat file", o.splats}});

  ProgressLine progress("splats verify");
  progress.show("reading " + o.splats);
  const SplatFile file = read_splat_file(o.splats);
  if (o.eps.empty()) check.eps = file.info.eps;
  if (!(check.eps > 0) || !std::isfinite(check.eps)) throw Error(o.splats + " records no eps; pass --eps");
  // About the splats' origin: a mesh far out that splats read about its centre is compared where they lie.
  const Winding winding = o.keep_winding ? Winding::AsGiven : Winding::Orient;
  // A failure names a mesh that is not where the splats' origin puts it, not the float steps of the
  // mismatch: it said "translate the mesh nearer the origin" of a mesh at the origin, or "no surface
  // area" of one that collapsed read about a far origin (read again as given where reading it
  // about the origin failed).
  std::optional<Mesh> loaded;
  const auto elsewhere = [&] { return origin_mismatch(file.info.origin, loaded ? *loaded : load_mesh(o.model, winding)); };
  std::optional<SurfaceCheckReport> checked;
  try {
    loaded = load_model(o.model, progress, winding, false, {ModelOrigin::Given, {}, file.info.origin});
    checked = check_surface(*loaded, file.splats, check, [&](const std::string& phase, double fraction) {
      progress.show(fmt::format("{} {:.0f}%", phase, 100 * fraction));
    });
  } catch (const Error& e) {
    if (const std::string mismatch = elsewhere(); !mismatch.empty()) throw Error(std::string(e.what()) + "; " + mismatch);
    throw;
  }
  const Mesh& mesh = *loaded;
  const SurfaceCheckReport& r = *checked;
  if (!o.json.empty()) {
    nlohmann::json json = to_json(r);
    json["model"] = o.model;
    json["splats_file"] = o.splats;
    write_file_atomically(o.json, json_text(json) + "\n");
  }
  progress.clear();

  const double eps = r.eps;
  fmt::print("verify     {} against {}, eps {:.6g}, seed {}\n", o.splats, o.model, eps, r.seed);
  std::string count = fmt::format("{} points checked", r.surface_points);
  if (r.surface_points_clamped)
    count += fmt::format(" (5 A / (pi eps^2) = {:.0f}, clamped to [{}, {}])", std::ceil(r.surface_points_wanted), kMinSurfacePoints,
                         kMaxSurfacePoints);
  fmt::print("surface    area {:.6g}, {}; uncovered {:.4g}% of the area ({} points)", r.surface_area, count, 100 * r.uncovered_fraction,
             r.uncovered_points);
  if (r.holes > 0)
    fmt::print(", {} holes, largest area {:.3g} ({:.3g} eps^2), diameter {:.3g} eps", r.holes, r.largest_hole_area,
               r.largest_hole_area / (eps * eps), r.largest_hole_diameter / eps);
  fmt::print("\n");
  fmt::print("splats     {} ({} points checked); largest distance to the surface {:.4g} = {:.4g} eps (splat {}); "
             "{:.4g}% of the splat area beyond eps; {} splats beyond eps\n",
             r.splats, r.splat_points, r.max_distance, r.max_distance_eps(), r.worst_splat, 100 * r.area_beyond_fraction, r.splats_beyond);
  fmt::print("shape      largest major semi-axis {:.4g} = {:.4g} of the diagonal; {} flipped, {} degenerate\n", r.largest_major,
             r.largest_major_diagonal(), r.flipped, r.degenerate);
  if (!r.ok()) {
    const std::string mismatch = elsewhere();
    throw Error(fmt::format("{}: fails the two-sided bound at eps {:.6g} against {}: {}", o.splats, eps, o.model,
                            mismatch.empty() ? describe_failure(r, &mesh) : describe_failure(r) + "; " + mismatch));
  }
  fmt::print("ok\n");
  return 0;
}

}  // namespace

Action register_splats(CLI::App& app) {
  auto* sub = app.add_subcommand("splats",
                                 "Elliptical splats from a mesh (OBJ, PLY, OFF, STL): sampling, kNN, per-sample splat fit "
                                 "on the OpenCL device, greedy selection and optimisation; writes a PLY of splats");
  auto o = std::make_shared<SplatsOptions>();
  add_device_option(*sub, o->device);
  sub->add_option("model", o->model, "Input mesh");
  sub->add_option("-o,--output", o->output, "Output splat PLY (position, normal, colour, major and minor semi-axis vectors and lengths). A mesh whose "
                  "coordinates are too coarse as floats for its size or eps (far from the origin) is read about the centre of its "
                  "bounding box: the positions are then relative to it, which the header records (splatcl_origin) and a warning names");
  sub->add_option("--format", o->format,
                  "Format of -o: splatcl (the splat PLY above) or 3dgs (3D Gaussian Splatting PLY: one flat Gaussian per "
                  "splat, sigma = semi-axis/2; 3DGS has no clip lines, so --clip splats are written unclipped, with a warning)")
      ->capture_default_str();
  sub->add_option("--stats", o->stats, "Write statistics (counts, reduction, errors against eps, time per phase) as JSON");
  sub->add_option("--render", o->render, "Also write an offscreen picture of the splats (.png or .exr): per-splat colours for grey models, else the splat colours");
  sub->add_flag("--reference", o->reference, "Fit with the native C++ reference instead of the OpenCL kernels");
  sub->add_flag("--strict", o->strict,
                "Refuse a model with problems (faces dropped for a non-finite vertex, an index out of range or unreadable, or fewer than 3 "
                "corners; zero-area or non-manifold faces; inconsistent orientation; faces pointing inward) instead of warning");
  sub->add_flag("--no-check", o->no_check,
                "Skip the end-of-run check of the two-sided bound against the mesh surface (the check of splatcl splats verify; "
                "without this flag a run whose splats break it exits 1 and writes nothing; with --thesis-only it only reports)");
  // The build parameters: the same list, names and meaning as `splatcl batch` manifest keys.
  add_parameter_options(*sub, splat_parameters(), to_json(SplatParameters{}), o->given);

  auto* verify = sub->add_subcommand("verify",
                                     "Check a splat file against the mesh surface, both ways: every point of every (clipped) "
                                     "splat within eps of the surface, and every point of the surface within eps of a splat "
                                     "that contains its projection and faces its way; exit 1 when either fails");
  auto v = std::make_shared<VerifyOptions>();
  verify->add_option("model", v->model, "The mesh the splats were made from")->required();
  verify->add_option("splats", v->splats, "Splat PLY written by splatcl splats")->required();
  verify->add_option("--eps", v->eps, "Tolerance to check (default: the one recorded in the file)")->type_name("E");
  verify->add_option("--points", v->points,
                     "Random surface points to check, 1000 to 20000000 (default: 5 A / (pi eps^2), enough to hit a hole of "
                     "diameter 2 eps 5 times, within [10000, 20000000])")
      ->type_name("N");
  verify->add_option("--ellipse-points", v->ellipse_points, "Area-uniform points per splat, 1 to 100000, besides its rim and clip chord (default 64)")
      ->type_name("M");
  verify->add_option("--seed", v->seed, "Seed of the random points (default 1)")->type_name("S");
  verify->add_option("--json", v->json, "Also write the measurements as JSON")->type_name("FILE");
  verify->add_flag("--keep-winding", v->keep_winding,
                   "Take the faces as wound in the file, for splats made with splatcl splats --keep-winding (by default they are "
                   "turned so that neighbours agree and closed parts face outward, as splatcl splats does)");
  return [o, v, verify] { return verify->parsed() ? run_verify(*v) : run_splats(*o); };
}

}  // namespace splatcl::cli
