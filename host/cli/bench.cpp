// splatcl bench [SUITE] [--quick] [--runs N] [--warmup N] [--device D ...] [--scaling size|threads]
//               [--json FILE] [--csv FILE] [--compare BASELINE.json [--threshold PCT]] [--plot DIR]
// splatcl bench report FILE.json
// splatcl bench compare RESULTS.json BASELINE.json [--threshold PCT]
// splatcl bench plot RESULTS.json -o DIR
// splatcl bench tune -o TUNING.json [--device D ...] [--kernel K ...] [--quick] [--runs N]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "bench/compare.hpp"
#include "bench/csv.hpp"
#include "bench/plot.hpp"
#include "bench/record.hpp"
#include "bench/report.hpp"
#include "bench/runner.hpp"
#include "bench/suites.hpp"
#include "bench/tune.hpp"
#include "primitives/tuning.hpp"
#include "cli/commands.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli {

namespace {

// --threshold: a percentage 0 to 10^6. CLI::Range let nan through (every comparison with it is
// false), and --compare then refused it only after the whole run, as "negative".
constexpr double kMaxThresholdPercent = 1e6;
std::string threshold_percent(const std::string& text) {
  double value = 0;
  try {
    std::size_t used = 0;
    value = std::stod(text, &used);
    if (used != text.size()) return "not a number: " + text;
  } catch (const std::exception&) {
    return "not a number: " + text;
  }
  return value >= 0 && value <= kMaxThresholdPercent ? std::string() : fmt::format("a percentage 0 to {:.0f}, not {}", kMaxThresholdPercent, text);
}

struct BenchOptions {
  bench::RunOptions run;
  std::string scaling = "none";
  std::string json_path, csv_path, compare_path, plot_dir;
  double threshold_pct = 10;
  // bench report / compare / plot
  std::string results_path, baseline_path, output_dir;
  // bench tune
  bench::TuneOptions tune;
  std::string tuning_path, tune_shape;
};

// Tunes, prints the gains, and writes the records into `path`: merged into the database already
// there (so `-o data/tuning.json` updates the shipped one), replacing records of the same kernel,
// shape and device.
int run_tune(const BenchOptions& o) {
  check_output_file(o.tuning_path, "-o");
  check_output_extension(o.tuning_path, "-o", {".json"}, "a tuning database, JSON");
  splatcl::TuningDatabase database;
  if (std::filesystem::exists(o.tuning_path)) {
    database = splatcl::TuningDatabase::read(o.tuning_path);
    primitives::check_database(database);  // its other records are written back as they are
  }
  bench::TuneOptions options = o.tune;
  if (!o.tune_shape.empty()) options.shapes = {parse_shape(o.tune_shape)};
  if (options.devices.empty())
    if (const char* env = std::getenv(kDeviceEnvVar); env && *env) options.devices.push_back(env);
  for (const auto& name : options.kernels) bench::parse_tuned_kernel(name);  // a typo fails before the run
  const auto results = bench::run_tuning(options);
  std::fputs(bench::tuning_report(results).c_str(), stdout);
  for (const auto& result : results) {
    // A smoke test's record over a full-size one: said, not refused (the user may mean it).
    const auto replaced = database.put(result.record);
    const auto size_of = [](const splatcl::TuningRecord& r) { return r.measured.is_object() ? r.measured.value("size", 0.0) : 0.0; };
    if (replaced && size_of(*replaced) > size_of(result.record))
      std::printf("note: %s (%s shape) replaces a record measured at %g elements with one measured at %g\n", result.record.kernel.c_str(),
                  result.record.shape.c_str(), size_of(*replaced), size_of(result.record));
  }
  database.write(o.tuning_path);
  std::printf("wrote %zu record(s) to %s\n", results.size(), o.tuning_path.c_str());
  return 0;
}

// Results from a .json file, or a .csv file written by --csv.
bench::Results read_any_results(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  bench::Results results = extension == ".csv" ? bench::read_csv(path) : bench::read_results(path);
  bench::require_distinct_records(results, path);
  return results;
}

// The run options, on `bench` itself and on every suite, so they may come before or after the suite.
void add_run_options(CLI::App& app, BenchOptions& o, bool takes_size, bool splats_models) {
  if (takes_size)
    app.add_option("--size", o.run.session.size, "Elements per case of the primitives suite (default: one key per pixel of 1920x1080)")
        ->capture_default_str()
        ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{std::numeric_limits<std::uint32_t>::max()}));
  app.add_flag("--quick", o.run.session.quick,
               "Small inputs and at most 2 runs and 1 warm-up unless --runs/--warmup, for smoke tests (figures not "
               "comparable); not with --size");
  app.add_option("--runs", o.run.session.measure.runs, "Timed runs per case; median, min and max are reported")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  app.add_option("--warmup", o.run.session.measure.warmup, "Untimed runs before timing (kernel builds, caches); 0 times the first build too")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  app.add_option("--device", o.run.devices,
                 "OpenCL device(s): index, type (cpu, gpu, simulator), name substring, or all (every device but simulators); "
                 "repeat or comma-separate for several, measured side by side in one run. Default $SPLATCL_DEVICE, else all")
      ->delimiter(',')
      ->check(empty_device_value)
      ->type_name("DEVICE");
  app.add_option("--scaling", o.scaling,
                 "size: every suite at 1/8, 1/4, 1/2 and 1x its problem sizes (--steps); threads: rerun "
                 "with POCL_MAX_PTHREAD_COUNT = 1 .. cores and merge")
      ->capture_default_str();
  app.add_option("--steps", o.run.size_steps, "Sizes of --scaling size (x2 steps ending at the standard size)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  app.add_option("--json", o.json_path, "Write the records to FILE (benchmark record format; whole or not at all)")->type_name("FILE");
  app.add_option("--csv", o.csv_path, "Write the records to FILE as CSV")->type_name("FILE");
  app.add_option("--compare", o.compare_path,
                 "Compare with a baseline results file (.json or .csv), read before the run; exit status 1 when a record's "
                 "median time and fastest run both grew by more than --threshold, 2 when no record matches one of the baseline")
      ->type_name("BASELINE");
  app.add_option("--threshold", o.threshold_pct, fmt::format("Regression threshold of --compare, in percent, 0..{:.0f}", kMaxThresholdPercent))
      ->capture_default_str()
      ->check(threshold_percent);
  app.add_option("--plot", o.plot_dir, "Also draw PNG plots with gnuplot into DIR (see 'bench plot')")->type_name("DIR");
  if (splats_models)
    app.add_option("--models", bench::splats_models_dir(), "Directory holding the test models (splats and csm suites)")
        ->capture_default_str();
}

// Regressions against the baseline: the table on stdout, the verdict as the exit status.
int report_comparison(const bench::Results& current, const std::string& baseline_path, double threshold_pct) {
  const bench::Results baseline = read_any_results(baseline_path);
  const bench::Comparison comparison = bench::compare_results(current, baseline, threshold_pct);
  std::fputs(("\n### comparison with " + baseline_path + "\n\n" + bench::comparison_report(comparison)).c_str(), stdout);
  // Runs measured differently or elsewhere compare, but say so: such changes read as regressions.
  for (const char* field : {"cpu_model", "logical_cores", "memory_gib", "build", "compiler", "opencl_device", "opencl_driver_version",
                            "pocl_max_pthread_count", "warmup", "quick", "tuning"}) {
    const auto a = baseline.machine.find(field), b = current.machine.find(field);
    if (a != baseline.machine.end() && b != current.machine.end() && *a != *b)
      std::printf("note: the runs differ in %s: %s in the baseline, %s here\n", field, a->dump().c_str(), b->dump().c_str());
  }
  std::fflush(stdout);
  if (comparison.matched.empty()) {  // nothing compared: not a verdict on the code (status 2, as a comparison that failed)
    std::fprintf(stderr, "splatcl: no record matches one in %s\n", printable(baseline_path).c_str());
    return 2;
  }
  if (comparison.regressions() > 0) {
    std::fprintf(stderr, "splatcl: %zu regression(s) beyond %g %% against %s\n", comparison.regressions(), threshold_pct,
                 baseline_path.c_str());
    return 1;
  }
  return 0;
}

// How often `name` was given on any of `apps` (the run options are on `bench` and on every suite).
std::size_t times_given(const std::vector<CLI::App*>& apps, const std::string& name) {
  std::size_t count = 0;
  for (CLI::App* app : apps)
    if (const CLI::Option* option = app->get_option_no_throw(name)) count += option->count();
  return count;
}

// --quick picks its own problem sizes: a --size beside it was silently replaced before.
void refuse_size_beside_quick(const std::vector<CLI::App*>& apps) {
  if (times_given(apps, "--size") > 0) throw Error("--quick sets its own problem sizes: drop --size or --quick");
}

void print_plots(const std::vector<std::string>& pngs) {
  for (const auto& png : pngs) std::printf("wrote %s\n", png.c_str());
}

}  // namespace

Action register_bench(CLI::App& app) {
  auto* bench = app.add_subcommand(
      "bench",
      "Time every kernel family on every OpenCL device against its native reference and peer libraries (no suite: all "
      "suites); a table on stdout, --json/--csv for records, --compare for regressions, --plot for PNGs");
  bench->require_subcommand(0, 1);
  auto options = std::make_shared<BenchOptions>();
  add_run_options(*bench, *options, true, true);

  std::vector<std::pair<CLI::App*, const bench::Suite*>> suite_commands;
  for (const auto& suite : bench::suites()) {
    auto* sub = bench->add_subcommand(suite.name, suite.description);
    const std::string_view name(suite.name);
    add_run_options(*sub, *options, suite.takes_size, name == "splats" || name == "csm");
    suite_commands.emplace_back(sub, &suite);
  }

  auto* report = bench->add_subcommand("report", "Print a results file written by --json (or --csv) as markdown tables, for docs");
  report->add_option("FILE", options->results_path, "Results written by 'splatcl bench --json'")->required()->type_name("FILE");

  auto* compare = bench->add_subcommand(
      "compare",
      "Compare a results file with a baseline. Exit status: 0 no regression; 1 a record's median time and fastest run both "
      "grew beyond the threshold; 2 no comparison (a file unreadable, or no record matches)");
  compare->add_option("RESULTS", options->results_path, "Results (.json or .csv)")->required()->type_name("RESULTS");
  compare->add_option("BASELINE", options->baseline_path, "Baseline results (.json or .csv)")->required()->type_name("BASELINE");
  compare->add_option("--threshold", options->threshold_pct,
                      fmt::format("Regression threshold, in percent (0..{:.0f}) of the baseline's median time and of its fastest run", kMaxThresholdPercent))
      ->capture_default_str()
      ->check(threshold_percent);

  auto* plot = bench->add_subcommand(
      "plot", "Draw PNG plots of a results file with gnuplot: throughput per case and device, size and thread scaling");
  plot->add_option("RESULTS", options->results_path, "Results (.json or .csv)")->required()->type_name("RESULTS");
  plot->add_option("-o,--output", options->output_dir, "Directory for plots.gp, its data and the PNGs")->required()->type_name("DIR");

  auto* tune = bench->add_subcommand(
      "tune",
      "Search the launch parameters of scan, compaction and radix sort (both shapes) on each device and write tuning "
      "records (data/tuning.json format), with each kernel's gain over the defaults");
  tune->add_option("-o,--output", options->tuning_path,
                   "Tuning database to write (atomically); records already in it for other kernels or devices are kept")
      ->required()
      ->type_name("FILE");
  tune->add_option("--device", options->tune.devices,
                   "OpenCL device(s) as for bench; default $SPLATCL_DEVICE, else every device present but simulators")
      ->delimiter(',')
      ->check(empty_device_value)
      ->type_name("DEVICE");
  tune->add_option("--kernel", options->tune.kernels, "Kernels to tune: scan, compact, radix-sort (default: all)")
      ->delimiter(',')
      ->type_name("KERNEL");
  tune->add_option("--size", options->tune.size, "Elements per problem")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{std::numeric_limits<std::uint32_t>::max()}));
  tune->add_option("--runs", options->tune.measure.runs, "Timed runs per candidate")->capture_default_str()->check(CLI::Range(1, 1000));
  tune->add_option("--shape", options->tune_shape, "Tune one shape only: cpu or gpu (default: both)")
      ->check(CLI::IsMember({"cpu", "gpu"}));
  tune->add_flag("--quick", options->tune.quick, "64k elements, 2 runs unless --runs: a smoke test (figures not comparable); not with --size");

  std::vector<CLI::App*> run_apps{bench};
  for (const auto& [sub, suite] : suite_commands) run_apps.push_back(sub);

  return [options, suite_commands, run_apps, report, compare, plot, tune] {
    bench::end_with_parent();
    BenchOptions& o = *options;
    if (tune->parsed()) {
      if (o.tune.quick) {
        refuse_size_beside_quick({tune});
        if (times_given({tune}, "--runs") == 0) o.tune.measure.runs = 2;  // a given --runs wins
      }
      return run_tune(o);
    }
    if (report->parsed()) {
      std::fputs(bench::markdown_report(read_any_results(o.results_path)).c_str(), stdout);
      return 0;
    }
    if (compare->parsed()) {
      // As diff and cmp: 0 no regression, 1 regressions, 2 no comparison (unreadable or unrelated files).
      try {
        const bench::Results current = read_any_results(o.results_path);
        return report_comparison(current, o.baseline_path, o.threshold_pct);
      } catch (const Error& e) {
        std::fprintf(stderr, "splatcl: %s\n", printable(e.what()).c_str());
        return 2;
      }
    }
    if (plot->parsed()) {
      print_plots(bench::write_plots(read_any_results(o.results_path), o.output_dir));
      return 0;
    }

    // The run options are on `bench` and on every suite: given on both, the suite's silently won
    // (`bench --json a.json primitives --json b.json` wrote b.json alone).
    for (const CLI::Option* option : run_apps.front()->get_options()) {
      const std::string name = option->get_name(false, true);
      if (name.rfind("--", 0) != 0 || name == "--help") continue;
      std::size_t levels = 0;
      for (CLI::App* a : run_apps)
        if (const CLI::Option* given = a->get_option_no_throw(name); given && given->count() > 0) ++levels;
      if (levels > 1) throw Error(name + " is given both before and after the suite's name: give it once");
    }
    if (times_given(run_apps, "--threshold") > 0 && o.compare_path.empty())
      throw Error("--threshold is the regression threshold of --compare: give --compare BASELINE too");
    if (times_given(run_apps, "--steps") > 0 && bench::parse_scaling(o.scaling) != bench::Scaling::Size)
      throw Error("--steps counts the sizes of --scaling size: give --scaling size too");

    std::vector<const bench::Suite*> chosen;
    for (const auto& [sub, suite] : suite_commands)
      if (sub->parsed()) chosen.push_back(suite);
    if (chosen.empty())
      for (const auto& suite : bench::suites()) chosen.push_back(&suite);

    // Fails before a long run, not after it, when a result could not be written.
    check_output_file(o.json_path, "--json");
    check_output_file(o.csv_path, "--csv");
    // JSON under a .csv name read back as broken CSV (bench report: "quote inside an unquoted cell").
    check_output_extension(o.json_path, "--json", {".json"}, "benchmark records, JSON");
    check_output_extension(o.csv_path, "--csv", {".csv"}, "benchmark records, CSV");
    check_distinct_outputs({{"--json", o.json_path}, {"--csv", o.csv_path}});
    // Written over, the baseline was compared with the run itself: "0 regressed".
    check_outputs_spare_inputs({{"--json", o.json_path}, {"--csv", o.csv_path}}, {{"--compare baseline", o.compare_path}});
    if (!o.compare_path.empty()) read_any_results(o.compare_path);  // a bad baseline fails before the run
    for (const bench::Suite* suite : chosen)
      if (suite->check_inputs) suite->check_inputs();  // a missing model fails before the other suites run
    if (!o.plot_dir.empty()) {
      // Not after the whole run: a plot directory that cannot be made, or no gnuplot.
      std::error_code error;
      std::filesystem::create_directories(o.plot_dir, error);
      check_writable_directory(o.plot_dir, "--plot " + o.plot_dir);
      if (bench::find_gnuplot().empty()) throw Error("--plot: gnuplot not found on PATH: install gnuplot-nox (scripts/setup.sh does)");
    }
    bench::RunOptions run = o.run;
    run.scaling = bench::parse_scaling(o.scaling);
    if (run.session.quick) {
      refuse_size_beside_quick(run_apps);
      // Few runs unless given: --quick --runs 5 used to run 2.
      if (times_given(run_apps, "--runs") == 0) run.session.measure.runs = std::min(run.session.measure.runs, 2);
      if (times_given(run_apps, "--warmup") == 0) run.session.measure.warmup = std::min(run.session.measure.warmup, 1);
    }
    if (run.devices.empty())
      if (const char* env = std::getenv(kDeviceEnvVar); env && *env) run.devices.push_back(env);
    if (run.scaling == bench::Scaling::Threads) run.arguments = bench::child_arguments(bench::own_arguments());

    const bench::Results results = bench::run_benchmarks(chosen, run);
    std::fputs(bench::markdown_report(results).c_str(), stdout);
    std::fflush(stdout);
    if (!o.json_path.empty()) bench::write_results(o.json_path, results);
    if (!o.csv_path.empty()) bench::write_csv(o.csv_path, results);
    if (!o.plot_dir.empty()) print_plots(bench::write_plots(results, o.plot_dir));
    if (!o.compare_path.empty()) return report_comparison(results, o.compare_path, o.threshold_pct);
    return 0;
  };
}

}  // namespace splatcl::cli
