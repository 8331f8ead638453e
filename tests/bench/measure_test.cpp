#include <gtest/gtest.h>

#include <vector>

#include "bench/measure.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

TEST(BenchMeasure, SummaryOfAnOddCountTakesTheMiddleSample) {
  const Summary s = summarize({9.0, 1.0, 5.0, 3.0, 7.0});
  EXPECT_DOUBLE_EQ(s.median_ms, 5.0);
  EXPECT_DOUBLE_EQ(s.min_ms, 1.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 9.0);
}

TEST(BenchMeasure, SummaryOfAnEvenCountAveragesTheMiddlePair) {
  const Summary s = summarize({4.0, 10.0, 2.0, 6.0});
  EXPECT_DOUBLE_EQ(s.median_ms, 5.0);
  EXPECT_DOUBLE_EQ(s.min_ms, 2.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 10.0);
}

TEST(BenchMeasure, SummaryOfOneSampleIsThatSample) {
  const Summary s = summarize({3.5});
  EXPECT_DOUBLE_EQ(s.median_ms, 3.5);
  EXPECT_DOUBLE_EQ(s.min_ms, 3.5);
  EXPECT_DOUBLE_EQ(s.max_ms, 3.5);
}

TEST(BenchMeasure, SummaryOfNothingIsAnError) { EXPECT_THROW(summarize({}), Error); }

TEST(BenchMeasure, RunsSetupEveryTimeAndKeepsOnlyTimedRuns) {
  int setups = 0, runs = 0;
  std::vector<int> progress;
  const Timing timing = measure_runs(
      MeasureOptions{2, 5}, [&] { ++setups; }, [&] { ++runs; }, nullptr,
      [&](int i, int total) {
        EXPECT_EQ(total, 7);
        progress.push_back(i);
      });
  EXPECT_EQ(setups, 7);
  EXPECT_EQ(runs, 7);
  EXPECT_EQ(timing.wall_ms.size(), 5u);
  EXPECT_EQ(progress, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(timing.device_ms.empty());
  for (double ms : timing.wall_ms) EXPECT_GE(ms, 0.0);
}

TEST(BenchMeasure, NoTimedRunsIsAnError) {
  EXPECT_THROW(measure_runs(MeasureOptions{1, 0}, {}, [] {}), Error);
}

TEST(BenchMeasure, PeakRssCoversMemoryTouchedSinceTheReset) {
  reset_peak_rss();
  const double before = peak_rss_mb();
  EXPECT_GT(before, 0.0);
  std::vector<char> block(64 << 20, 1);  // 64 MiB, touched
  const double after = peak_rss_mb();
  EXPECT_GE(after, before + 60.0) << "block[0] = " << int(block[0]);
}

}  // namespace
}  // namespace splatcl::bench
