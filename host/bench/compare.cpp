#include "bench/compare.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "runtime/error.hpp"

namespace splatcl::bench {

std::string comparison_key(const Record& record) {
  std::string key = record.suite + "/" + record.case_name + "/" + record.impl + "/" + record.device;
  if (record.size) key += fmt::format("/{} {}", *record.size, record.size_unit);
  // In name order: a JSON file and a CSV of the same run list the fields in different orders, and
  // every record with two of them ("bits", "shape") failed to match across the two.
  std::vector<std::pair<std::string, std::string>> fields;
  for (const auto& [field, value] : record.extra.items()) {
    // Measured figures, not identity.
    if (value.is_structured() || field == "bytes" || field == "flops" || field == "device_total_ms") continue;
    fields.emplace_back(field, value.is_string() ? value.get<std::string>() : value.dump());
  }
  std::sort(fields.begin(), fields.end());
  for (const auto& [field, value] : fields) key += "/" + field + "=" + value;
  return key;
}

void require_distinct_records(const Results& results, const std::string& path) {
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < results.records.size(); ++i) {
    const std::string key = comparison_key(results.records[i]);
    if (const auto [at, fresh] = first.emplace(key, i); !fresh)
      throw Error(fmt::format("{}: records {} and {} are the same row ({})", path, at->second, i, key));
  }
}

std::size_t Comparison::regressions() const {
  return static_cast<std::size_t>(std::count_if(matched.begin(), matched.end(), [](const ComparedRecord& r) { return r.regression; }));
}

Comparison compare_results(const Results& current, const Results& baseline, double threshold_pct) {
  if (!(threshold_pct >= 0)) throw Error(fmt::format("the regression threshold must be 0 or more, not {}", threshold_pct));
  Comparison comparison;
  comparison.threshold_pct = threshold_pct;
  std::map<std::string, const Record*> base;
  for (const auto& record : baseline.records) base.emplace(comparison_key(record), &record);
  std::map<std::string, bool> seen;
  for (const auto& record : current.records) {
    const std::string key = comparison_key(record);
    const auto it = base.find(key);
    if (it == base.end()) {
      comparison.only_current.push_back(key);
      continue;
    }
    seen[key] = true;
    ComparedRecord compared;
    compared.key = key;
    compared.baseline_ms = it->second->median_ms;
    compared.current_ms = record.median_ms;
    const auto change = [](double before, double after) { return before > 0 ? (after - before) / before * 100.0 : 0.0; };
    compared.change_pct = change(compared.baseline_ms, compared.current_ms);
    compared.min_change_pct = change(it->second->min_ms, record.min_ms);
    compared.regression = compared.change_pct > threshold_pct && compared.min_change_pct > threshold_pct;
    comparison.matched.push_back(compared);
  }
  for (const auto& record : baseline.records) {
    const std::string key = comparison_key(record);
    if (!seen.count(key)) comparison.only_baseline.push_back(key);
  }
  return comparison;
}

std::string comparison_report(const Comparison& comparison) {
  if (comparison.matched.empty())  // two unrelated files: the counts, not every key of both
    return fmt::format("no record matches: {} here, {} in the baseline (other suites, devices or sizes)\n", comparison.only_current.size(),
                       comparison.only_baseline.size());
  std::string text = "| record | baseline ms | current ms | change | fastest run's change | |\n|---|---:|---:|---:|---:|---|\n";
  for (const auto& r : comparison.matched)
    text += fmt::format("| {} | {:.3f} | {:.3f} | {:+.1f} % | {:+.1f} % | {} |\n", r.key, r.baseline_ms, r.current_ms, r.change_pct,
                        r.min_change_pct, r.regression ? "**regression**" : "");
  for (const auto& key : comparison.only_current) text += "\nnot in the baseline: " + key;
  for (const auto& key : comparison.only_baseline) text += "\nonly in the baseline: " + key;
  if (!comparison.only_current.empty() || !comparison.only_baseline.empty()) text += "\n";
  text += fmt::format("\n{} of {} matched records regressed by more than {:g} % (median time and fastest run).\n", comparison.regressions(),
                      comparison.matched.size(), comparison.threshold_pct);
  return text;
}

}  // namespace splatcl::bench
