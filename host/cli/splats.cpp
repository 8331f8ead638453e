// splatcl splats: mesh → elliptical splats (sampling, kNN, per-sample fit and growth on the OpenCL
// device, greedy selection, optimisation) → PLY and statistics JSON; `splatcl splats verify` checks
// a splat file against its model.
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/parameter_options.hpp"
#include "cli/progress.hpp"
#include "io/atomic_file.hpp"
#include "runtime/error.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/render.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::splats;

struct SplatsOptions {
  DeviceOptions device;
  std::string model, output, stats, render;
  bool reference = false;
  std::shared_ptr<GivenParameters> given = std::make_shared<GivenParameters>();  // the build parameters given
};

struct VerifyOptions {
  std::string model, splats;
  double eps = 0;
};

int run_splats(const SplatsOptions& o) {
  if (o.model.empty()) throw Error("splats: a MODEL is required (see splatcl splats --help)");
  if (o.output.empty()) throw Error("splats: an output file is required (-o OUT.ply)");
  // The same parameters, parsing and translation as `splatcl batch` (splats/pipeline_options.hpp).
  SplatParameters params;
  for (const auto& [option, value] : *o.given) set_parameter(params, option, value);
  validate(params);
  ProgressLine progress("splats");
  progress.show("loading " + o.model);
  Stopwatch load_clock;
  const Mesh mesh = load_mesh(o.model);
  const double load_ms = load_clock.elapsed_ms();
  const SplatSetup setup = splat_setup(params, mesh, o.model);
  const PipelineOptions& options = setup.options;
  const ColorSource& colors = setup.colors;
  const double diagonal = setup.diagonal;
  const std::string& color_description = setup.color_description;
  std::shared_ptr<Runtime> runtime;
  if (!o.reference) runtime = Runtime::create(o.device.device);
  SplatRun run = generate_splats(mesh, colors, options, runtime.get(), [&](const std::string& phase) { progress.show(phase); });
  run.phases.insert(run.phases.begin(), {"load", load_ms});
  progress.show("writing " + o.output);
  Stopwatch write_clock;
  write_splat_file(o.output, run.records(), splat_file_info(setup, run, o.model));
  run.phases.push_back({"write", write_clock.elapsed_ms()});
  const nlohmann::json stats = splat_statistics(run, setup, o.model, o.output);
  if (!o.stats.empty()) write_file_atomically(o.stats, stats.dump(2) + "\n");
  if (!o.render.empty()) {
    progress.show("rendering " + o.render);
    RenderOptions view;
    view.random_colors = colors.field == ColorField::Grey && !colors.texture;
    render_splats(o.render, run.records(), view);
  }
  progress.clear();

  const double n = static_cast<double>(run.samples.size()), m = static_cast<double>(run.selected.size());
  fmt::print("model      {} ({} vertices, {} faces, bbox diagonal {:.6g})\n", o.model, mesh.vertices.size(), mesh.face_count(), diagonal);
  fmt::print("samples    {} ({}; {} duplicates dropped), k = {}\n", run.samples.size(), to_string(options.sampling),
             run.samples.duplicates_dropped, run.neighbors.k);
  fmt::print("eps        {:.6g} ({:.3g} of the diagonal), colour tolerance {} ({})\n", options.fit.eps, options.fit.eps / diagonal,
             options.fit.color_tolerance, color_description);
  fmt::print("splats     {} ({:.1f}% of the samples, {:.2f} samples per splat); greedy {}, then {} swaps and {} removals in {} rounds\n",
             run.selected.size(), 100.0 * m / n, n / m, run.greedy_count, run.optimise.swaps, run.optimise.removals, run.optimise.rounds);
  fmt::print("error      before selection mean {:.3g} ({:.1f}% of eps); after mean {:.3g} ({:.1f}%), max {:.3g} ({:.1f}%)\n",
             run.before.mean, 100 * run.before.mean / options.fit.eps, run.after.mean, 100 * run.after.mean / options.fit.eps,
             run.after.max, 100 * run.after.max / options.fit.eps);
  std::string timing = "time      ";
  for (const auto& p : run.phases) timing += fmt::format(" {} {:.0f} ms,", p.phase, p.ms);
  timing.pop_back();
  fmt::print("{}; total {:.2f} s (fit on {})\n", timing, run.total_ms() / 1000.0, run.fit_backend);
  fmt::print("wrote      {}{}{}\n", o.output, o.stats.empty() ? "" : ", " + o.stats, o.render.empty() ? "" : ", " + o.render);
  return 0;
}

int run_verify(const VerifyOptions& o) {
  ProgressLine progress("splats");
  progress.show("reading " + o.splats);
  const SplatFile file = read_splat_file(o.splats);
  const float eps = static_cast<float>(o.eps > 0 ? o.eps : file.info.eps);
  if (!(eps > 0)) throw Error(o.splats + " records no eps; pass --eps");
  progress.show("sampling " + o.model);
  const Mesh mesh = load_mesh(o.model);
  const Samples samples = sample_mesh(mesh, parse_sampling(file.info.sampling.empty() ? "vertices" : file.info.sampling), ColorSource{});
  progress.show("checking coverage");
  const VerifyReport report = verify_splats(samples, file.splats, eps);
  progress.clear();
  fmt::print("splats     {} from {} ({} samples, {}), eps {:.6g}\n", report.splats, o.model, report.samples,
             file.info.sampling, eps);
  fmt::print("coverage   {} of {} samples covered; {} splats cover no sample\n", report.samples - report.uncovered,
             report.samples, report.empty_splats);
  fmt::print("error      mean {:.3g} = {:.1f}% of eps, max {:.3g} = {:.1f}% of eps\n", report.mean_error,
             100 * report.mean_error / eps, report.max_error, 100 * report.max_error / eps);
  if (!report.ok())
    throw Error(fmt::format("{}: {} samples uncovered, {} splats cover no sample", o.splats, report.uncovered, report.empty_splats));
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
  sub->add_option("-o,--output", o->output, "Output splat PLY (position, normal, colour, major and minor semi-axis vectors and lengths)");
  sub->add_option("--stats", o->stats, "Write statistics (counts, reduction, errors against eps, time per phase) as JSON");
  sub->add_option("--render", o->render, "Also write an offscreen picture of the splats (PNG): per-splat colours for grey models, else the splat colours");
  sub->add_flag("--reference", o->reference, "Fit with the native C++ reference instead of the OpenCL kernels");
  // The build parameters: the same list, names and meaning as `splatcl batch` manifest keys.
  add_parameter_options(*sub, splat_parameters(), to_json(SplatParameters{}), o->given);

  auto* verify = sub->add_subcommand("verify", "Check a splat file against its model: every sample covered within eps, no empty splat; reports mean error / eps");
  auto v = std::make_shared<VerifyOptions>();
  verify->add_option("model", v->model, "The mesh the splats were made from")->required();
  verify->add_option("splats", v->splats, "Splat PLY written by splatcl splats")->required();
  verify->add_option("--eps", v->eps, "Tolerance to check (default: the one recorded in the file)");
  return [o, v, verify] { return verify->parsed() ? run_verify(*v) : run_splats(*o); };
}

}  // namespace splatcl::cli
