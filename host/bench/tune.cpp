#include "bench/tune.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "bench/record.hpp"
#include "bench/runner.hpp"
#include "cli/progress.hpp"
#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace prim = splatcl::primitives;
using prim::LaunchParameters;
using prim::Primitive;

using prim::kPrimitives;
constexpr std::uint64_t kTuneSeed = 0x70E5u;

// The values `bench tune` tries for each parameter; the defaults are among them.
std::vector<std::int64_t> candidate_values(const std::string& name) {
  if (name == "chunks_per_compute_unit") return {1, 2, 4, 8, 16, 32};
  if (name == "min_chunk_items") return {std::int64_t{1} << 13, std::int64_t{1} << 15, std::int64_t{1} << 17};
  if (name == "digit_bits") return {6, 7, 8, 9, 10};
  if (name == "group_size") return {32, 64, 128, 256, 512, 1024};
  return {1, 2, 4, 8, 16};  // items_per_work_item
}

// One primitive's benchmark problem: the case of `bench primitives` it speeds up most directly.
class Workload {
 public:
  virtual ~Workload() = default;
  // Builds the driver; throws Error when the device or the kernels refuse the parameters.
  virtual void prepare(Shape shape, const LaunchParameters& parameters) = 0;
  virtual void setup() {}
  virtual void run() = 0;
  // Throws Error naming `what` when the output differs from the reference.
  virtual void check(const std::string& what) = 0;
  virtual const char* unit() const = 0;
};

// Exclusive scan of 16-bit values.
class ScanWorkload : public Workload {
 public:
  ScanWorkload(Runtime& runtime, std::size_t n) : runtime_(runtime), n_(n), values_(random_keys(n, 16, kTuneSeed)), expected_(n) {
    prim::reference::scan(values_, expected_, prim::ScanKind::Exclusive);
    in_ = upload(runtime, values_, "scan input");
    out_ = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(cl_uint), "scan output");
  }
  void prepare(Shape shape, const LaunchParameters& parameters) override { scanner_.emplace(runtime_, shape, parameters); }
  // The output holds no earlier candidate's result: one that writes nothing would pass the check,
  // time fastest, and be written into the database.
  void setup() override { poison_buffer(runtime_, out_, n_ * sizeof(cl_uint)); }
  void run() override {
    scanner_->run(in_, out_, n_, prim::ScanKind::Exclusive, false);
    finish(runtime_);
  }
  void check(const std::string& what) override { expect_same_output(what, download<std::uint32_t>(runtime_, out_, n_), expected_); }
  const char* unit() const override { return "elements"; }

 private:
  Runtime& runtime_;
  std::size_t n_;
  std::vector<std::uint32_t> values_, expected_;
  cl::Buffer in_, out_;
  std::optional<prim::Scanner> scanner_;
};

// Unique of sorted 20-bit keys: the distinct cluster keys of a frame.
class CompactWorkload : public Workload {
 public:
  CompactWorkload(Runtime& runtime, std::size_t n) : runtime_(runtime), n_(n) {
    auto keys = random_keys(n, kClusterKeyBits, kTuneSeed + 1);
    std::sort(keys.begin(), keys.end());
    expected_ = prim::reference::unique(keys);
    in_ = upload(runtime, keys, "unique input");
    out_ = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(cl_uint), "unique output");
  }
  void prepare(Shape shape, const LaunchParameters& parameters) override { compactor_.emplace(runtime_, shape, parameters); }
  void setup() override { poison_buffer(runtime_, out_, n_ * sizeof(cl_uint)); }  // as ScanWorkload's
  void run() override {
    kept_ = compactor_->unique(in_, out_, n_);
    finish(runtime_);
  }
  void check(const std::string& what) override { expect_same_output(what, download<std::uint32_t>(runtime_, out_, kept_), expected_); }
  const char* unit() const override { return "keys"; }

 private:
  Runtime& runtime_;
  std::size_t n_, kept_ = 0;
  std::vector<std::uint32_t> expected_;
  cl::Buffer in_, out_;
  std::optional<prim::Compactor> compactor_;
};

// Radix sort of 20-bit keys (a frame's cluster keys), keys only.
class RadixSortWorkload : public Workload {
 public:
  RadixSortWorkload(Runtime& runtime, std::size_t n) : runtime_(runtime), n_(n) {
    const auto keys = random_keys(n, kClusterKeyBits, kTuneSeed + 2);
    expected_ = keys;
    std::sort(expected_.begin(), expected_.end());
    in_ = upload(runtime, keys, "sort input");
    work_ = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(cl_uint), "sort keys");
  }
  void prepare(Shape shape, const LaunchParameters& parameters) override {
    sorter_.emplace(runtime_, prim::KeyType::U32, false, shape, parameters);
  }
  void setup() override { copy_buffer(runtime_, in_, work_, n_ * sizeof(cl_uint)); }
  void run() override {
    sorter_->sort(work_, nullptr, n_, kClusterKeyBits);
    finish(runtime_);
  }
  void check(const std::string& what) override { expect_same_output(what, download<std::uint32_t>(runtime_, work_, n_), expected_); }
  const char* unit() const override { return "keys"; }

 private:
  Runtime& runtime_;
  std::size_t n_;
  std::vector<std::uint32_t> expected_;
  cl::Buffer in_, work_;
  std::optional<prim::RadixSorter> sorter_;
};

std::unique_ptr<Workload> make_workload(Primitive primitive, Runtime& runtime, std::size_t n) {
  switch (primitive) {
    case Primitive::Scan: return std::make_unique<ScanWorkload>(runtime, n);
    case Primitive::Compact: return std::make_unique<CompactWorkload>(runtime, n);
    default: return std::make_unique<RadixSortWorkload>(runtime, n);
  }
}

class Tuner {
 public:
  Tuner(Runtime& runtime, const TuneOptions& options) : runtime_(runtime), options_(options) {}

  TuneResult tune(Primitive primitive, Shape shape, std::size_t n) {
    workload_ = make_workload(primitive, runtime_, n);
    label_ = fmt::format("{} ({} shape) on '{}'", prim::tuning_name(primitive), to_string(shape), runtime_.info().name);
    TuneResult result;
    result.device = runtime_.info().name;
    result.best = result.defaults;
    double best_ms = measure(shape, result.defaults, primitive, result);
    std::vector<LaunchParameters> tried{result.defaults};
    // One parameter at a time, each over its candidates with the others at their best so far.
    for (const auto& name : prim::tunable_parameters(primitive, shape)) {
      for (const std::int64_t value : candidate_values(name)) {
        LaunchParameters candidate = result.best;
        prim::set_parameter(candidate, name, value);
        if (std::find(tried.begin(), tried.end(), candidate) != tried.end()) continue;
        tried.push_back(candidate);
        try {  // a value beyond the device's or the kernels' limits, or one the compiler rejects
          prim::validate(candidate, primitive, shape, runtime_.info());
          workload_->prepare(shape, candidate);
        } catch (const Error&) {
          ++result.refused;
          continue;
        }
        const double ms = measure(shape, candidate, primitive, result);
        if (ms < best_ms) {
          best_ms = ms;
          result.best = candidate;
        }
      }
    }
    // The reported gain: defaults and best again, alternating, so that drift on a shared machine
    // falls on both.
    std::vector<double> default_runs, best_runs;
    for (int round = 0; round < 2; ++round) {
      append_runs(shape, result.defaults, default_runs);
      // When the search kept the defaults, both series time the same launch: one pooled median, so
      // that noise between them is not reported as a gain.
      append_runs(shape, result.best, result.best == result.defaults ? default_runs : best_runs);
    }
    result.default_ms = summarize(default_runs).median_ms;
    result.best_ms = best_runs.empty() ? result.default_ms : summarize(best_runs).median_ms;
    // A search winner that loses the side-by-side runs was noise: the record keeps the defaults.
    if (result.best_ms >= result.default_ms) {
      result.best = result.defaults;
      result.best_ms = result.default_ms;
    }
    result.record = record_for_device(prim::tuning_name(primitive), to_string(shape), runtime_.info());
    for (const auto& name : prim::tunable_parameters(primitive, shape)) result.record.parameters[name] = prim::parameter(result.best, name);
    result.record.measured = {{"size", n},
                              {"size_unit", workload_->unit()},
                              {"default_ms", result.default_ms},
                              {"tuned_ms", result.best_ms},
                              {"gain", result.best_ms > 0 ? result.default_ms / result.best_ms : 1.0},
                              {"candidates", result.candidates},
                              {"date", machine_info(nullptr).value("date", "")}};
    return result;
  }

 private:
  // Median time of one candidate; its output must equal the reference.
  double measure(Shape shape, const LaunchParameters& parameters, Primitive primitive, TuneResult& result) {
    std::vector<double> runs;
    append_runs(shape, parameters, runs);
    ++result.candidates;
    // On a terminal one updating line; in a log a line every SPLATCL_PROGRESS_SECONDS (there was none).
    progress_.show(fmt::format("{}: {} {:.3f} ms", label_, prim::describe(parameters, primitive, shape), summarize(runs).median_ms));
    return summarize(runs).median_ms;
  }

  void append_runs(Shape shape, const LaunchParameters& parameters, std::vector<double>& runs) {
    workload_->prepare(shape, parameters);
    const Timing timing = measure_runs(options_.measure, [&] { workload_->setup(); }, [&] { workload_->run(); });
    workload_->check("tune " + label_);
    runs.insert(runs.end(), timing.wall_ms.begin(), timing.wall_ms.end());
  }

  Runtime& runtime_;
  const TuneOptions& options_;
  std::unique_ptr<Workload> workload_;
  std::string label_;
  cli::ProgressLine progress_{"splatcl bench tune"};
};

}  // namespace

Primitive parse_tuned_kernel(const std::string& name) {
  if (const auto primitive = prim::parse_tuning_name(name)) return *primitive;
  throw Error("unknown kernel '" + name + "' to tune (one of: " + prim::kTuningNames + ")");
}

std::vector<TuneResult> run_tuning(const TuneOptions& options) {
  std::vector<Primitive> chosen;
  for (const auto& name : options.kernels) chosen.push_back(parse_tuned_kernel(name));
  if (chosen.empty()) chosen.assign(std::begin(kPrimitives), std::end(kPrimitives));
  const auto n = static_cast<std::size_t>(options.quick ? std::uint64_t{1} << 16 : options.size);
  std::vector<TuneResult> results;
  for (const DeviceInfo& device : bench_devices(options.devices)) {
    Runtime runtime(device);
    Tuner tuner(runtime, options);
    for (const Primitive primitive : chosen)
      for (const Shape shape : options.shapes) results.push_back(tuner.tune(primitive, shape, n));
  }
  return results;
}

std::string tuning_report(const std::vector<TuneResult>& results) {
  std::string text = "| kernel | shape | device | tuned parameters (defaults) | default ms | tuned ms | gain |\n"
                     "|---|---|---|---|---:|---:|---:|\n";
  for (const auto& r : results) {
    const Primitive primitive = parse_tuned_kernel(r.record.kernel);
    const Shape shape = parse_shape(r.record.shape);
    std::string parameters;
    for (const auto& name : prim::tunable_parameters(primitive, shape)) {
      const auto tuned = prim::parameter(r.best, name), by_default = prim::parameter(r.defaults, name);
      parameters += (parameters.empty() ? "" : ", ") + fmt::format("{}={}", name, tuned) +
                    (tuned == by_default ? "" : fmt::format(" ({})", by_default));
    }
    text += fmt::format("| {} | {} | {} | {} | {:.3f} | {:.3f} | {:.2f}× |\n", r.record.kernel, r.record.shape, r.device, parameters,
                        r.default_ms, r.best_ms, r.best_ms > 0 ? r.default_ms / r.best_ms : 1.0);
  }
  return text;
}

}  // namespace splatcl::bench
