#pragma once
// `splatcl bench tune`: searches the launch parameters of the primitives (primitives/tuning.hpp) on
// each device and shape, one parameter at a time from the defaults (each candidate validated
// against the device first, its output compared with the reference), and reports the best against
// the defaults, both measured again side by side; a winner that loses that comparison was noise, and
// the record keeps the defaults. The results are tuning records
// (runtime/tuning.hpp) for data/tuning.json.
#include <cstdint>
#include <string>
#include <vector>

#include "bench/measure.hpp"
#include "bench/session.hpp"
#include "primitives/tuning.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::bench {

struct TuneOptions {
  std::vector<std::string> devices;  // selectors as for --device; empty: every device but simulators
  std::vector<std::string> kernels;  // "scan", "compact", "radix-sort"; empty: all three
  std::vector<Shape> shapes{Shape::Cpu, Shape::Gpu};
  std::uint64_t size = kFullHdPixels;
  bool quick = false;  // 64k elements (the CLI also takes 2 runs): figures not comparable
  MeasureOptions measure{1, 5};
};

struct TuneResult {
  TuningRecord record;  // the best parameters, with "measured" filled in
  std::string device;   // the device's name
  primitives::LaunchParameters defaults, best;
  double default_ms = 0, best_ms = 0;  // medians of the final side-by-side runs
  int candidates = 0, refused = 0;     // measured, and refused by validation (device or kernel limits)
};

// The primitives `bench tune` knows, by tuning name.
primitives::Primitive parse_tuned_kernel(const std::string& name);

// Tunes every chosen kernel in both shapes on every chosen device.
std::vector<TuneResult> run_tuning(const TuneOptions& options);

// The markdown table of `results`: kernel, shape, device, parameters, default and tuned medians, gain.
std::string tuning_report(const std::vector<TuneResult>& results);

}  // namespace splatcl::bench
