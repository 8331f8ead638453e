// --scaling size on every suite: each one runs at every x2 step, its sizes follow the scale, the
// streaming-copy rows are measured once, and the records are well formed, survive the JSON file and
// plot as size-scaling curves. Small scales keep every suite to a few seconds.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bench/plot.hpp"
#include "bench/report.hpp"
#include "bench/runner.hpp"
#include "bench/suites.hpp"
#include "bench_models.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

struct ScalingCase {
  const char* suite;
  double scale;           // of the larger step (the smaller one is half of it)
  const char* main_case;  // a case whose size is the scaled quantity itself
  bool stream_copy;       // whether the suite measures the streaming-copy bandwidth
};

const Suite& suite_named(const std::string& name) {
  for (const Suite& s : suites())
    if (name == s.name) return s;
  throw Error("no suite " + name);
}

class BenchSizeScaling : public testing::TestWithParam<ScalingCase> {};

TEST_P(BenchSizeScaling, EverySuiteRunsAtEveryStepWithWellFormedRecords) {
  const ScalingCase param = GetParam();
  if (const std::string missing = missing_bench_model(param.suite); !missing.empty())
    GTEST_SKIP() << missing << " not found";
  RunOptions options;
  options.session.quick = true;
  options.session.measure = MeasureOptions{0, 1};
  options.session.scale = param.scale;
  // The default device (PoCL here), not index 0: with setup.sh's implementations registered, that
  // is Oclgrind, a simulator far too slow for these sizes.
  options.devices = {std::to_string(choose_device("").index)};
  options.scaling = Scaling::Size;
  options.size_steps = 2;
  const Results results = run_benchmarks({&suite_named(param.suite)}, options);

  // Sizes and record counts per row (case, implementation, problem variant); the ceilings (stream-copy,
  // peak-fma) once.
  std::map<std::string, std::set<std::uint64_t>> sizes;
  std::map<std::string, std::vector<std::uint64_t>> sizes_in_order;  // the runner goes from the smallest step up
  std::map<std::string, int> records_per_row, stream_rows;
  for (const Record& r : results.records) {
    const std::string what = case_label(r) + " " + impl_label(r);
    EXPECT_EQ(r.suite, param.suite) << what;
    EXPECT_FALSE(r.device.empty()) << what;
    EXPECT_EQ(r.runs, 1) << what;
    EXPECT_GT(r.median_ms, 0.0) << what;
    EXPECT_LE(r.min_ms, r.median_ms) << what;
    EXPECT_LE(r.median_ms, r.max_ms) << what;
    ASSERT_TRUE(r.size.has_value()) << what;
    ASSERT_TRUE(r.throughput.has_value()) << what;
    EXPECT_NEAR(*r.throughput, static_cast<double>(*r.size) / (r.median_ms * 1e-3), 1e-9 * *r.throughput) << what;
    EXPECT_EQ(r.throughput_unit, r.size_unit + "/s") << what;
    if (r.case_name == "stream-copy" || r.case_name == "peak-fma") {
      ++stream_rows[r.case_name + " " + r.impl];
      continue;
    }
    sizes[what].insert(*r.size);
    sizes_in_order[what].push_back(*r.size);
    ++records_per_row[what];
  }
  EXPECT_EQ(stream_rows.size(), param.stream_copy ? 4u : 0u);  // three copies, one FMA peak
  for (const auto& [impl, count] : stream_rows) EXPECT_EQ(count, 1) << impl;

  ASSERT_FALSE(sizes.empty());
  bool main_case_seen = false;
  for (const auto& [what, seen] : sizes) {
    // Every row at both steps. Sizes that depend on the frame's content (clusters) may coincide;
    // none grows when the scale shrinks.
    EXPECT_EQ(records_per_row[what], 2) << what;
    EXPECT_TRUE(std::is_sorted(sizes_in_order[what].begin(), sizes_in_order[what].end())) << what;
    if (what.rfind(std::string(param.main_case) + " ", 0) != 0) continue;
    main_case_seen = true;
    ASSERT_EQ(seen.size(), 2u) << what;
    const double ratio = static_cast<double>(*seen.rbegin()) / static_cast<double>(*seen.begin());
    EXPECT_NEAR(ratio, 2.0, 0.1) << what;
  }
  EXPECT_TRUE(main_case_seen) << param.main_case;

  // The records survive the results file, and plot as size-scaling curves.
  const fs::path dir = fs::temp_directory_path() / ("splatcl-bench-scaling-" + std::string(param.suite) + "-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_results((dir / "results.json").string(), results);
  const Results read = read_results((dir / "results.json").string());
  ASSERT_EQ(read.records.size(), results.records.size());
  for (std::size_t k = 0; k < read.records.size(); ++k) EXPECT_EQ(to_json(read.records[k]), to_json(results.records[k]));
  if (!find_gnuplot().empty()) {
    const auto pngs = write_plots(read, (dir / "plots").string());
    const std::string wanted = (dir / "plots" / ("scaling-size-" + std::string(param.suite) + ".png")).string();
    EXPECT_NE(std::find(pngs.begin(), pngs.end(), wanted), pngs.end()) << wanted;
    EXPECT_GT(fs::file_size(wanted), 0u);
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

INSTANTIATE_TEST_SUITE_P(AllSuites, BenchSizeScaling,
                         testing::Values(ScalingCase{"primitives", 0.25, "scan-exclusive", true}, ScalingCase{"cluster", 0.25, "keys", true},
                                         ScalingCase{"splats", 0.125, "fit", false}, ScalingCase{"csm", 1.0, "capture", true}),
                         [](const testing::TestParamInfo<ScalingCase>& test) { return std::string(test.param.suite); });

// The suite list and the test list agree: a new suite must be added above.
TEST(BenchScalingSuites, CoversEverySuite) {
  std::set<std::string> names;
  for (const Suite& s : suites()) names.insert(s.name);
  EXPECT_EQ(names, (std::set<std::string>{"primitives", "cluster", "splats", "csm"}));
}

}  // namespace
}  // namespace splatcl::bench
