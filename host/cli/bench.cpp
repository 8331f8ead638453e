// splatcl bench <suite> [--size N] [--runs N] [--warmup N] [--device D] [--json FILE]
// splatcl bench report FILE.json
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "bench/record.hpp"
#include "bench/report.hpp"
#include "bench/session.hpp"
#include "bench/suites.hpp"
#include "cli/commands.hpp"

namespace splatcl::cli {

Action register_bench(CLI::App& app) {
  auto* bench = app.add_subcommand(
      "bench", "Time every kernel against its native reference and peer libraries; a table on stdout, --json for records");
  bench->require_subcommand(1);

  struct Options {
    bench::SessionOptions session;
    DeviceOptions device;
    std::string report_path;
  };
  auto options = std::make_shared<Options>();

  std::vector<std::pair<CLI::App*, const bench::Suite*>> suite_commands;
  for (const auto& suite : bench::suites()) {
    auto* sub = bench->add_subcommand(suite.name, suite.description);
    if (suite.takes_size)
      sub->add_option("--size", options->session.size, "Elements per case (default: one key per pixel of 1920x1080)")
          ->capture_default_str()
          ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{std::numeric_limits<std::uint32_t>::max()}));
    sub->add_option("--runs", options->session.measure.runs, "Timed runs per case; median, min and max are reported")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000000));
    sub->add_option("--warmup", options->session.measure.warmup,
                    "Untimed runs before timing (kernel builds, caches); 0 times the first build too")
        ->capture_default_str()
        ->check(CLI::Range(0, 1000000));
    sub->add_option("--json", options->session.json_path, "Also write the records to FILE (written whole or not at all)")
        ->type_name("FILE");
    add_device_option(*sub, options->device);
    if (std::string_view(suite.name) == "splats") sub->add_option("--models", bench::splats_models_dir(), "Directory holding the models")->capture_default_str();
    suite_commands.emplace_back(sub, &suite);
  }

  auto* report = bench->add_subcommand("report", "Print a results file written by --json as a markdown table, for docs");
  report->add_option("FILE", options->report_path, "Results JSON written by 'splatcl bench <suite> --json'")
      ->required()
      ->type_name("FILE");

  return [options, suite_commands, report] {
    if (report->parsed()) {
      std::fputs(bench::markdown_report(bench::read_results(options->report_path)).c_str(), stdout);
      return 0;
    }
    for (const auto& [sub, suite] : suite_commands) {
      if (!sub->parsed()) continue;
      bench::SessionOptions session_options = options->session;
      session_options.device = options->device.device;
      bench::Session session(suite->name, session_options);
      suite->run(session);
      session.finish();
    }
    return 0;
  };
}

}  // namespace splatcl::cli
