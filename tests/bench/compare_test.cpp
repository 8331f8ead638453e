// Regression check against a baseline: an identical run passes, a slower record beyond the threshold
// is flagged, one within it is not, and records are matched by their full identity.
#include <gtest/gtest.h>

#include "bench/compare.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

Record record(const std::string& case_name, const std::string& impl, double median_ms, const Json& extra = Json::object()) {
  Record r;
  r.suite = "primitives";
  r.case_name = case_name;
  r.impl = impl;
  r.device = impl == kImplReference ? kHostDevice : "pthread-test";
  r.size = 1000;
  r.size_unit = "keys";
  r.runs = 3;
  r.median_ms = r.min_ms = r.max_ms = median_ms;
  r.extra = extra;
  return r;
}

Results baseline() {
  Results results;
  results.records = {record("radix-sort-u32", kImplOpenCL, 10, Json{{"bits", 20}, {"shape", "cpu"}}),
                     record("radix-sort-u32", kImplOpenCL, 40, Json{{"bits", 20}, {"shape", "gpu"}}),
                     record("radix-sort-u32", kImplReference, 20, Json{{"bits", 20}}),
                     record("scan-exclusive", kImplOpenCL, 5, Json{{"shape", "cpu"}, {"device_ms", {{"scan", 4.0}}}})};
  return results;
}

TEST(BenchCompare, IdenticalResultsPass) {
  const Comparison c = compare_results(baseline(), baseline(), 5);
  EXPECT_EQ(c.matched.size(), 4u);
  EXPECT_EQ(c.regressions(), 0u);
  EXPECT_TRUE(c.only_current.empty());
  EXPECT_TRUE(c.only_baseline.empty());
  EXPECT_NE(comparison_report(c).find("0 of 4 matched records regressed by more than 5 %"), std::string::npos);
}

TEST(BenchCompare, SlowerBeyondTheThresholdIsARegression) {
  Results current = baseline();
  current.records[1].median_ms = current.records[1].min_ms = 50;  // gpu shape +25 %
  current.records[3].median_ms = current.records[3].min_ms = 5.2;  // scan +4 %
  current.records[2].median_ms = current.records[2].min_ms = 10;   // reference faster: never a regression
  const Comparison c = compare_results(current, baseline(), 10);
  ASSERT_EQ(c.matched.size(), 4u);
  EXPECT_EQ(c.regressions(), 1u);
  EXPECT_TRUE(c.matched[1].regression);
  EXPECT_NEAR(c.matched[1].change_pct, 25.0, 1e-9);
  EXPECT_FALSE(c.matched[3].regression);
  EXPECT_NEAR(c.matched[3].change_pct, 4.0, 1e-9);
  EXPECT_FALSE(c.matched[2].regression);
  const std::string report = comparison_report(c);
  EXPECT_NE(report.find("**regression**"), std::string::npos);
  EXPECT_NE(report.find("shape=gpu"), std::string::npos);
  // A lower threshold catches the scan too.
  EXPECT_EQ(compare_results(current, baseline(), 3).regressions(), 2u);
}

// Noise on a shared machine only adds time: a median that grew while the fastest run did not is
// noise, not a regression (two identical quick runs flagged 28 of 36 records on medians alone).
TEST(BenchCompare, ASlowerMedianWithAnUnchangedFastestRunIsNoise) {
  Results current = baseline();
  current.records[0].median_ms = 30, current.records[0].max_ms = 60;  // +200 % median, fastest run 10 as before
  current.records[1].median_ms = 60, current.records[1].min_ms = 46;  // +50 % median, fastest run +15 %
  const Comparison c = compare_results(current, baseline(), 10);
  EXPECT_FALSE(c.matched[0].regression);
  EXPECT_NEAR(c.matched[0].change_pct, 200.0, 1e-9);
  EXPECT_NEAR(c.matched[0].min_change_pct, 0.0, 1e-9);
  EXPECT_TRUE(c.matched[1].regression);
  EXPECT_NEAR(c.matched[1].min_change_pct, 15.0, 1e-9);
  EXPECT_EQ(c.regressions(), 1u);
  EXPECT_EQ(compare_results(current, baseline(), 20).regressions(), 0u);  // the fastest run's 15 % is within 20
}

// Unrelated files (another suite): the counts, not every key of both.
TEST(BenchCompare, NoMatchReportsCountsOnly) {
  Results other = baseline();
  for (Record& r : other.records) r.suite = "csm";
  const Comparison c = compare_results(other, baseline(), 10);
  EXPECT_TRUE(c.matched.empty());
  EXPECT_EQ(comparison_report(c), "no record matches: 4 here, 4 in the baseline (other suites, devices or sizes)\n");
}

TEST(BenchCompare, MatchesByFullIdentity) {
  Results current = baseline();
  current.records[0].extra["bits"] = 32;      // another problem variant: not comparable
  current.records[3].device = "other device";  // another device
  const Comparison c = compare_results(current, baseline(), 10);
  EXPECT_EQ(c.matched.size(), 2u);
  EXPECT_EQ(c.only_current.size(), 2u);
  EXPECT_EQ(c.only_baseline.size(), 2u);
  // Measured figures are not identity.
  Results timed = baseline();
  timed.records[3].extra["device_ms"] = Json{{"scan", 9.0}};
  timed.records[3].extra["bytes"] = 8000;
  timed.records[3].extra["device_total_ms"] = 9.0;
  EXPECT_EQ(comparison_key(timed.records[3]), comparison_key(baseline().records[3]));
  // The fields in another order (a CSV of the same run lists them in its columns' order): the same
  // record. Before, every record with two fields failed to match across JSON and CSV.
  Json reordered = Json::object();
  reordered["shape"] = "cpu";
  reordered["bits"] = 20;
  Record csv_row = baseline().records[0];
  csv_row.extra = reordered;
  ASSERT_EQ(csv_row.extra.begin().key(), "shape") << "the test needs an insertion-ordered Json";
  EXPECT_EQ(comparison_key(csv_row), comparison_key(baseline().records[0]));
}

TEST(BenchCompare, NegativeThresholdIsAnError) { EXPECT_THROW(compare_results(baseline(), baseline(), -1), Error); }

}  // namespace
}  // namespace splatcl::bench
