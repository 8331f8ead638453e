#include "bench/session.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include <fmt/format.h>

#include <cstdlib>

#include "io/json_keys.hpp"
#include "bench/report.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::bench {

namespace {

Record record_of(const Case& c, const std::string& suite, const std::string& device_name) {
  Record record;
  record.suite = suite;
  record.case_name = c.name;
  record.impl = c.impl;
  record.device = c.on_device ? device_name : kHostDevice;
  if (c.size > 0) {
    record.size = c.size;
    record.size_unit = c.size_unit;
  }
  record.extra = c.extra;
  return record;
}

Json merged(Json fields, const Json& more) {
  for (const auto& [key, value] : more.items()) fields[key] = value;
  return fields;
}

}  // namespace

Case opencl_case(const std::string& name, Shape shape, std::uint64_t size, const std::string& size_unit,
                 const Json& problem, const Json& implementation) {
  return {name, kImplOpenCL, true, size, size_unit,
          merged(merged(problem, implementation), Json{{"shape", to_string(shape)}})};
}

Case reference_case(const std::string& name, std::uint64_t size, const std::string& size_unit, const Json& problem,
                    const Json& implementation) {
  return {name, kImplReference, false, size, size_unit, merged(problem, implementation)};
}

std::string describe(const Case& c) {
  const Record record = record_of(c, "", "");
  return case_label(record) + " " + impl_label(record);
}

Session::Session(std::string suite, SessionOptions options)
    : suite_(std::move(suite)),
      options_(std::move(options)),
      runtime_(Runtime::create(options_.device)),
      progress_(::isatty(::fileno(stderr)) != 0),
      log_(progress_ ? nullptr : std::make_unique<cli::ProgressLine>("splatcl bench " + suite_)) {
  if (options_.measure.runs < 1) throw Error("--runs must be at least 1");
  if (options_.measure.warmup < 0) throw Error("--warmup must not be negative");
  // Fail before a long run, not after it, when the results could not be written.
  if (!options_.json_path.empty()) {
    const std::filesystem::path target(options_.json_path);
    const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir))
      throw Error("cannot write " + options_.json_path + ": directory " + dir.string() + " does not exist");
  }
}

const Record& Session::measure(const Case& c, const std::function<void()>& setup, const std::function<void()>& run,
                               Profiler* profiler) {
  Record record = record_of(c, suite_, runtime_->info().name);
  const std::string label = describe(c);
  if (!c.on_device && !options_.measure_host) {
    show_progress(label + ": measured with the first device", false);
    if (setup) setup();
    run();
    unrecorded_ = std::move(record);
    return unrecorded_;
  }

  const bool exact_peak = reset_peak_rss();
  const Timing timing = measure_runs(options_.measure, setup, run, profiler,
                                     [&](int i, int total) {
                                       // Warm-ups apart from the timed runs ("run 2/2" for --runs 1 before).
                                       const int warmups = total - options_.measure.runs;
                                       show_progress(i < warmups ? fmt::format("{}: warm-up {}/{}", label, i + 1, warmups)
                                                                 : fmt::format("{}: run {}/{}", label, i - warmups + 1, options_.measure.runs),
                                                     false);
                                     });
  const Summary summary = summarize(timing.wall_ms);
  record.runs = static_cast<int>(timing.wall_ms.size());
  record.median_ms = summary.median_ms;
  record.min_ms = summary.min_ms;
  record.max_ms = summary.max_ms;
  if (record.size && summary.median_ms > 0) {
    record.throughput = static_cast<double>(*record.size) / (summary.median_ms * 1e-3);
    record.throughput_unit = record.size_unit + "/s";
  }
  // Without a resettable peak the process-wide peak would mislead more than help.
  if (exact_peak) record.peak_rss_mb = peak_rss_mb();
  if (!timing.device_ms.empty()) {
    Json per_kernel = Json::object();
    for (const auto& [kernel, ms] : timing.device_ms) per_kernel[kernel] = ms;
    record.extra["device_ms"] = std::move(per_kernel);
    record.extra["device_total_ms"] = timing.device_total_ms;
  }
  show_progress(fmt::format("{}: {:.3f} ms median", label, record.median_ms), true);
  records_.push_back(std::move(record));
  return records_.back();
}

std::string tuning_used(const DeviceInfo& device) {
  const char* tuning = std::getenv(kTuningEnvVar);
  const std::string source = tuning && *tuning ? tuning : "embedded data/tuning.json";
  // Whether the database has a record for this device at all: one with none runs every kernel
  // at its defaults, which the database's name alone did not say.
  const auto database = TuningDatabase::active();
  const bool applies = std::any_of(database->records().begin(), database->records().end(),
                                   [&](const TuningRecord& r) { return r.matches(device); });
  return applies ? source : source + " (no record for this device: defaults)";
}

Results Session::results() const {
  Results results;
  results.machine = machine_info(&runtime_->info());
  // How the run measured, for compare: a --warmup 0 run (it times the kernel build) or another
  // tuning database read as plain regressions beside a default run.
  results.machine["warmup"] = options_.measure.warmup;
  results.machine["quick"] = options_.quick;  // small problems: figures not comparable with a full run's
  results.machine["tuning"] = tuning_used(runtime_->info());
  results.records = records_;
  return results;
}

void Session::finish() const {
  const Results all = results();
  std::fputs(markdown_report(all).c_str(), stdout);
  std::fflush(stdout);
  if (!options_.json_path.empty()) write_results(options_.json_path, all);
}

void finish(Runtime& runtime) {
  try {
    runtime.queue().finish();
  } catch (...) {
    rethrow_as_error("waiting for the benchmark kernels");
  }
}

void copy_buffer(Runtime& runtime, const cl::Buffer& from, const cl::Buffer& to, std::size_t bytes) {
  try {
    if (bytes > 0) runtime.queue().enqueueCopyBuffer(from, to, 0, 0, bytes);
    runtime.queue().finish();
  } catch (...) {
    rethrow_as_error("restoring benchmark input");
  }
}

void poison_buffer(Runtime& runtime, const cl::Buffer& buffer, std::size_t bytes) {
  try {
    if (bytes > 0) runtime.queue().enqueueFillBuffer(buffer, cl_uchar{0xA5}, 0, bytes);
    runtime.queue().finish();
  } catch (...) {
    rethrow_as_error("clearing a benchmark output");
  }
}

std::vector<std::uint32_t> random_keys(std::size_t n, unsigned bits, std::uint64_t seed) {
  std::mt19937 rng(static_cast<std::uint32_t>(seed));
  const std::uint32_t mask = bits >= 32 ? ~0u : (1u << bits) - 1u;
  std::vector<std::uint32_t> keys(n);
  for (auto& key : keys) key = static_cast<std::uint32_t>(rng()) & mask;
  return keys;
}

std::uint64_t scaled(const Session& session, std::uint64_t standard) {
  const double value = std::round(static_cast<double>(standard) * session.options().scale);
  return value < 1 ? 1 : static_cast<std::uint64_t>(value);
}

Session::~Session() {
  // An error leaving a case half-way must not print its message on the end of the progress line.
  if (progress_line_open_) std::fputc('\n', stderr);
}

void Session::withdraw_last_record(const std::string& why) {
  if (!records_.empty()) records_.pop_back();
  if (progress_line_open_) std::fputc('\n', stderr);
  progress_line_open_ = false;
  std::fprintf(stderr, "splatcl: warning: %s; that row is left out\n", printable(why).c_str());
}

void Session::show_progress(const std::string& text, bool final_line) {
  if (log_) return log_->show(text);
  // \r and erase-line keep one updating line per case.
  std::fprintf(stderr, "\r\033[K[bench %s] %s%s", suite_.c_str(), text.c_str(), final_line ? "\n" : "");
  std::fflush(stderr);
  progress_line_open_ = !final_line;
}

}  // namespace splatcl::bench
