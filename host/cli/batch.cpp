// splatcl batch: many meshes → splats and coherent shadow maps, resumable, shardable over machines;
// `splatcl batch merge` combines the summaries of the shards of one run.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "batch/manifest.hpp"
#include "io/json_keys.hpp"
#include "batch/runner.hpp"
#include "batch/shard.hpp"
#include "batch/summary.hpp"
#include "cli/commands.hpp"
#include "cli/model_input.hpp"
#include "cli/parameter_options.hpp"
#include "cli/progress.hpp"
#include "io/atomic_file.hpp"
#include "io/file_lock.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::batch;
namespace fs = std::filesystem;

// Exit status when the run completed but at least one model failed (docs/batch.md).
constexpr int kSomeModelsFailed = 2;

struct BatchCommand {
  DeviceOptions device;
  std::string input, output, shard = "0/1", summary;
  unsigned jobs = 1;
  bool force = false, list = false, reference = false;
  // Parameter options (the splat and CSM build parameters): kept as given and validated by the
  // manifest's own rules, as the command-line layer of every model's parameters.
  std::shared_ptr<GivenParameters> given = std::make_shared<GivenParameters>();
  std::optional<std::string> outputs;  // given empty, it is refused as "outputs": [] is (it built both)
};

struct MergeCommand {
  std::vector<std::string> summaries;
  std::string output;
  bool partial = false;
};

std::string bar(std::size_t done, std::size_t total) {
  constexpr std::size_t width = 24;
  const std::size_t filled = total ? done * width / total : width;
  return "[" + std::string(filled, '#') + std::string(width - filled, '.') + "]";
}

nlohmann::json overrides_of(const BatchCommand& c) {
  nlohmann::json overrides = nlohmann::json::object();
  for (const auto& [option, value] : *c.given) overrides[parameter_key(option)] = value;
  if (c.outputs) {
    nlohmann::json names = nlohmann::json::array();
    std::string name;
    // Every name between the commas, empty ones too: set_outputs refuses them (",," passed).
    for (const char ch : *c.outputs + ",") {
      if (ch != ',') {
        name += ch;
      } else {
        names.push_back(name);
        name.clear();
      }
    }
    if (c.outputs->empty()) names = nlohmann::json::array();
    overrides["outputs"] = names;
  }
  return overrides;
}

std::string describe_outputs(const ModelResult& r) {
  std::string text;
  for (const auto& o : r.outputs)
    text += fmt::format("{}{} {}", text.empty() ? "" : ", ", o.kind, o.reused ? "reused" : fmt::format("built in {:.2f} s", o.build_ms / 1000));
  return text;
}

int run_batch_command(const BatchCommand& c) {
  if (c.input.empty()) throw Error("batch: an INPUT manifest (.json, .csv) or directory of meshes is required (see splatcl batch --help)");
  const Shard shard = parse_shard(c.shard);
  if (c.jobs == 0) throw Error("--jobs 0: not a whole number 1 or more");
  if (c.output.empty() && !c.list) throw Error("batch: an output directory is required (-o OUTDIR)");
  const nlohmann::json overrides = overrides_of(c);
  std::error_code ec;
  const bool input_is_directory = fs::is_directory(c.input, ec);
  const std::vector<ModelEntry> all = input_is_directory ? scan_directory(c.input, c.output, overrides) : load_manifest(c.input, overrides);
  for (const auto& [a, b] : ids_differing_in_case_only(all))
    queue_warning(c.input, fmt::format("model ids '{}' and '{}' differ only in letter case: on a case-insensitive file system "
                                       "(macOS, Windows, an SMB share) their outputs are the same files; give one another \"id\"",
                                       a, b));
  const std::vector<ModelEntry> models = select_shard(all, shard);
  if (c.list) {
    for (const auto& m : models) fmt::print("{}\t{}\n", m.id, m.input);
    return 0;
  }
  const std::string summary_path = c.summary.empty() ? (fs::path(c.output) / summary_name(shard)).string() : c.summary;
  // Before any work: nothing the run writes may replace what it reads, every output must be
  // writable, and no other run may be building these models here (held until the summary is written).
  // The locks come before anything is removed: check_output_file clears the summary's dead
  // temporaries, and "dead" means no such pid on this node, which a copy on another node may be.
  check_run_paths(c.input, input_is_directory, c.output, summary_path, all);
  const auto locks = lock_models(models, c.output, summary_path);  // makes the output directory
  check_output_file(summary_path, "--summary");

  RunInfo info;
  info.input = c.input;
  info.output_dir = c.output;
  info.working_directory = fs::current_path().string();
  info.manifest_checksum = manifest_checksum(all);
  info.manifest_models = all.size();
  info.shard = shard;
  info.jobs = c.jobs;
  info.device = c.reference ? "reference" : choose_device(c.device.device).name;  // fails early without a device
  info.started = utc_now();

  RunOptions options;
  options.output_dir = c.output;
  options.device = c.device.device;
  options.jobs = c.jobs;
  options.force = c.force;
  options.reference = c.reference;
  Stopwatch clock;
  ProgressLine progress("batch");
  const auto show = [&](std::size_t done, std::size_t total, std::size_t failed, const std::string& now) {
    const double elapsed = clock.elapsed_ms() / 1000;
    const std::string eta = done ? fmt::format(", about {:.0f} s left", elapsed / static_cast<double>(done) * static_cast<double>(total - done)) : "";
    progress.show(fmt::format("{} {}/{} models{}, {:.0f} s{} | {}", bar(done, total), done, total,
                              failed ? fmt::format(", {} failed", failed) : "", elapsed, eta, now));
  };
  const auto finished = [&](const ModelResult& r) {
    progress.clear();
    if (r.ok) fmt::print("{:<8}{} ({}){}\n", r.reused() ? "reused" : "ok", r.id, describe_outputs(r), r.warning.empty() ? "" : "; warning: " + r.warning);
    else fmt::print("{:<8}{}: {}\n", "FAILED", r.id, r.reason);
    std::fflush(stdout);
  };
  // An earlier run's summary would no longer match the files once this run rewrites any: an
  // interrupted run left it in place, naming other parameters and checksums. Removed after every
  // check (a run refused for its device has touched nothing), a summary on disk is always of a run
  // that finished.
  if (!fs::remove(summary_path, ec) && ec)
    throw Error(fmt::format("cannot remove the earlier summary {}: {}", summary_path, ec.message()));
  if (!models.empty()) show(0, models.size(), 0, "starting");
  const std::vector<ModelResult> results = run_batch(models, options, show, finished);
  progress.clear();
  info.wall_s = clock.elapsed_ms() / 1000;
  const nlohmann::json summary = make_summary(info, results);
  write_file_atomically(summary_path, json_text(summary) + "\n");

  const auto& counts = summary["counts"];
  fmt::print("batch   {} of {} models{}: {} ok ({} reused), {} failed in {:.1f} s; summary {}\n", models.size(), all.size(),
             shard.whole() ? "" : fmt::format(" (shard {}/{})", shard.index, shard.count), counts["ok"].get<std::size_t>(),
             counts["reused"].get<std::size_t>(), counts["failed"].get<std::size_t>(), info.wall_s, summary_path);
  const std::size_t failed = counts["failed"];
  if (failed == 0) return 0;
  std::fflush(stdout);
  std::fprintf(stderr, "splatcl: batch: %zu of %zu models failed (reasons in %s)\n", failed, models.size(), summary_path.c_str());
  return kSomeModelsFailed;
}

int run_merge(const MergeCommand& c) {
  if (c.output.empty()) throw Error("batch merge: an output file is required (-o MERGED.json)");
  // Any folder's lock file may be live (an output directory's, or a summary folder's of a run
  // elsewhere): renamed over, the next run would open the new file and not see the old locks.
  if (std::filesystem::path(c.output).filename() == kLockFileName)
    throw Error(fmt::format("batch merge: -o {} is a batch run's lock file", c.output));
  check_output_file(c.output, "-o");
  std::vector<std::pair<std::string, std::string>> inputs;
  for (const auto& path : c.summaries) inputs.emplace_back("shard summary", path);
  check_outputs_spare_inputs({{"-o", c.output}}, inputs);
  std::vector<std::pair<std::string, nlohmann::json>> named;
  for (const auto& path : c.summaries) named.emplace_back(path, read_summary(path));
  // Nor the files of the run, as its summaries name them (paths as the run was given them): -o
  // naming a model's mesh or one of its outputs overwrote it without a word, where batch refuses
  // such a --summary.
  for (const auto& [name, summary] : named) {
    // The summary's paths are as the run was given them: relative ones from the run's working
    // directory (merged elsewhere, they named other files, and the run's own were overwritten).
    // Summaries from before 2026-12-07 do not record it, and one recorded on another machine may
    // not exist here: their paths are taken from here.
    std::filesystem::path base = summary.value("working_directory", "");
    if (std::error_code ec; !base.empty() && !std::filesystem::is_directory(base, ec)) base.clear();
    const auto at_run = [&](const std::string& path) { return (base / path).string(); };
    // The manifest too: batch refuses it as --summary, and merged over it the next run failed on
    // the summary's keys.
    if (summary.contains("input") && summary["input"].is_string()) inputs.emplace_back("manifest of the run", at_run(summary["input"]));
    const std::string output_dir = summary.value("output_dir", "").empty() ? "" : at_run(summary.value("output_dir", ""));
    if (!output_dir.empty()) inputs.emplace_back("lock file of the run", (std::filesystem::path(output_dir) / kLockFileName).string());
    for (const auto& model : summary.at("models")) {
      const std::string id = model.at("id");
      if (model.contains("input") && model["input"].is_string())
        inputs.emplace_back(fmt::format("input of model '{}'", id), at_run(model["input"]));
      if (output_dir.empty()) continue;
      for (const std::string& file : output_names(id))
        inputs.emplace_back(fmt::format("output of model '{}'", id), (std::filesystem::path(output_dir) / file).string());
    }
  }
  check_outputs_spare_inputs({{"-o", c.output}}, inputs);
  const nlohmann::json merged = merge_summaries(named, c.partial);
  write_file_atomically(c.output, json_text(merged) + "\n");
  const auto& counts = merged["counts"];
  fmt::print("merged  {} summaries: {} models, {} ok ({} reused), {} failed; wrote {}\n", named.size(), counts["models"].get<std::size_t>(),
             counts["ok"].get<std::size_t>(), counts["reused"].get<std::size_t>(), counts["failed"].get<std::size_t>(), c.output);
  const std::size_t failed = counts["failed"];
  if (failed == 0) return 0;
  std::fflush(stdout);
  std::fprintf(stderr, "splatcl: batch merge: %zu of %zu models failed (reasons in %s)\n", failed, counts["models"].get<std::size_t>(),
               c.output.c_str());
  return kSomeModelsFailed;
}

}  // namespace

Action register_batch(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "batch",
      "Many meshes → splat PLYs and coherent shadow maps, with statistics and a summary JSON; resumable (finished outputs are "
      "verified by checksum and skipped) and shardable over machines (--shard i/N). Exit status: 0 every model ok; 1 an error, "
      "nothing ran (bad manifest, option or device), or the summary could not be written; 2 the run completed but some models failed. See docs/batch.md");
  auto c = std::make_shared<BatchCommand>();
  add_device_option(*sub, c->device);
  sub->add_option("input", c->input, "Manifest (.json or .csv) or a directory of meshes (OBJ, PLY, OFF, STL; searched recursively)");
  sub->add_option("-o,--output", c->output, "Output directory: ID.splats.ply/.json, ID.csm/.csm.json, ID.batch.json per model, and the summary");
  sub->add_option("--shard", c->shard, "Process shard i of N (0 <= i < N): the models whose rank in id order is i modulo N")->capture_default_str();
  sub->add_option("--jobs", c->jobs, "Models processed at once (each with its own OpenCL context)")->capture_default_str()->type_name("COUNT");
  sub->add_option("--summary", c->summary, "Summary file (default OUTDIR/summary.json, or OUTDIR/summary-I-of-N.json for a shard)");
  sub->add_flag("--force", c->force, "Rebuild every output even when a matching one exists");
  sub->add_flag("--list", c->list, "Print the models of this shard (id and input, tab-separated) and exit");
  sub->add_flag("--reference", c->reference, "Use the native C++ references instead of the OpenCL kernels");
  // Parameters for every model (a manifest's "defaults" and a model's own keys take part as
  // documented): the options of `splatcl splats` and `splatcl csm build`, from the same lists.
  add_parameter_options(*sub, splats::splat_parameters(), splats::to_json(splats::SplatParameters{}), c->given);
  add_parameter_options(*sub, csm::csm_parameters(), csm::to_json(csm::CsmParameters{}), c->given);
  sub->add_option("--outputs", c->outputs, "Outputs per model: splats, csm or splats,csm (default both)");

  auto* merge = sub->add_subcommand("merge", "Combine the summaries of the shards of one run into one summary (checks that every shard "
                                             "is present once and no model appears twice). Exit status: 0 every model ok; 1 the "
                                             "summaries cannot be merged; 2 some models failed");
  auto m = std::make_shared<MergeCommand>();
  merge->add_option("summaries", m->summaries, "Shard summaries (summary-I-of-N.json)")->required();
  merge->add_option("-o,--output", m->output, "Merged summary file");
  merge->add_flag("--partial", m->partial, "Merge even when some shards are missing");
  return [c, m, merge] { return merge->parsed() ? run_merge(*m) : run_batch_command(*c); };
}

}  // namespace splatcl::cli
