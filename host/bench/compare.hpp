#pragma once
// Regression check of a benchmark run against a baseline results file: records are matched by
// suite, case, impl, device, size and every scalar extra field (problem variant, kernel shape,
// implementation variant, thread count); a matched record whose median time and fastest run both
// grew by more than the threshold is a regression (noise on a shared machine only adds time, so a
// slowdown that the fastest run does not show is noise: two identical quick runs here flagged 28
// of 36 records on medians alone).
#include <string>
#include <vector>

#include "bench/record.hpp"

namespace splatcl::bench {

// The identity of a record across runs: "cluster/compact/opencl/<device>/2073600 keys/shape=cpu ...".
std::string comparison_key(const Record& record);
// Throws Error "PATH: records I and J are the same row (KEY)" when two records of `results` share
// a comparison_key: report, compare and plot took one of them silently.
void require_distinct_records(const Results& results, const std::string& path);

struct ComparedRecord {
  std::string key;
  double baseline_ms = 0, current_ms = 0;  // median times
  double change_pct = 0;  // (current − baseline) / baseline × 100 of the medians; positive = slower
  double min_change_pct = 0;  // the same of the fastest runs (min_ms)
  bool regression = false;  // both changes beyond the threshold
};

struct Comparison {
  double threshold_pct = 0;
  std::vector<ComparedRecord> matched;  // in the current run's order
  std::vector<std::string> only_current, only_baseline;
  std::size_t regressions() const;
};

// Throws Error for a negative threshold.
Comparison compare_results(const Results& current, const Results& baseline, double threshold_pct);

// A markdown table of the matched records, regressions flagged, then the unmatched keys and a
// summary line.
std::string comparison_report(const Comparison& comparison);

}  // namespace splatcl::bench
