// bench csm --quick: every CSM kernel family on the bunny, beside the native reference (and Embree
// for the capture), with the record fields the docs tables and plots need.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "bench/report.hpp"
#include "bench/session.hpp"
#include "bench/suites.hpp"
#include "bench_models.hpp"

namespace splatcl::bench {
namespace {

TEST(BenchCsmSuite, QuickRunMeasuresEveryCaseWithPositiveThroughput) {
  if (const std::string missing = missing_bench_model("csm"); !missing.empty()) GTEST_SKIP() << missing << " not found";
  SessionOptions options;
  options.quick = true;
  options.measure = MeasureOptions{0, 1};
  Session session("csm", options);
  run_csm_suite(session);
  const auto& records = session.records();

  std::set<std::pair<std::string, std::string>> seen;
  for (const Record& r : records) {
    if (r.case_name == "stream-copy" || r.case_name == "peak-fma") continue;  // the ceilings, checked by the session tests
    seen.insert({r.case_name, r.impl});
    EXPECT_EQ(r.suite, "csm");
    EXPECT_EQ(r.runs, 1);
    ASSERT_TRUE(r.size.has_value()) << r.case_name;
    EXPECT_GT(*r.size, 0u);
    ASSERT_TRUE(r.throughput.has_value()) << r.case_name << " " << r.impl;
    EXPECT_GT(*r.throughput, 0.0) << r.case_name << " " << r.impl;
    EXPECT_EQ(r.throughput_unit, r.size_unit + "/s");
    EXPECT_LE(r.min_ms, r.median_ms);
    EXPECT_LE(r.median_ms, r.max_ms);
    EXPECT_EQ(r.extra.value("model", ""), "stanford-bunny");
    EXPECT_EQ(r.device == kHostDevice, r.impl != kImplOpenCL) << r.case_name << " " << r.impl;
    if (r.impl == kImplOpenCL) {
      EXPECT_TRUE(r.extra.contains("device_ms")) << r.case_name;
    }
  }
  const std::pair<const char*, const char*> units[] = {{"capture", "rays"}, {"compress", "samples"}, {"visibility", "queries"}, {"ao", "samples"}};
  for (const auto& [name, unit] : units) {
    EXPECT_TRUE(seen.count({name, kImplOpenCL})) << name;
    EXPECT_TRUE(seen.count({name, kImplReference})) << name;
    const auto it = std::find_if(records.begin(), records.end(), [&](const Record& r) { return r.case_name == name; });
    ASSERT_NE(it, records.end());
    EXPECT_EQ(it->size_unit, unit) << name;
  }
  // Both capture methods, each beside its reference.
  for (const char* variant : {"raycast", "raster"})
    for (const char* impl : {kImplOpenCL, kImplReference})
      EXPECT_EQ(std::count_if(records.begin(), records.end(),
                              [&](const Record& r) {
                                return r.case_name == "capture" && r.impl == impl && r.extra.value("variant", "") == variant;
                              }),
                1)
          << variant << " " << impl;
  // Capture and compression measure the same maps: one ray per sample.
  const auto size_of = [&](const char* name) {
    return *std::find_if(records.begin(), records.end(), [&](const Record& r) { return r.case_name == name; })->size;
  };
  EXPECT_EQ(size_of("capture"), size_of("compress"));
  EXPECT_EQ(size_of("capture"), 8u * 32u * 32u);
#ifdef SPLATCL_HAVE_EMBREE
  const auto embree = std::find_if(records.begin(), records.end(), [](const Record& r) { return r.impl == "embree"; });
  ASSERT_NE(embree, records.end());
  EXPECT_EQ(embree->case_name, "capture");
  ASSERT_TRUE(embree->extra.contains("rays_cast"));
  EXPECT_EQ(embree->extra["rays_cast"]["first"].get<std::uint64_t>(), *embree->size);
  EXPECT_GT(embree->extra["rays_cast"]["second"].get<std::uint64_t>(), 0u);
  EXPECT_LE(embree->extra["rays_cast"]["second"].get<std::uint64_t>(), *embree->size);
#endif
  // The report compares each row with its reference.
  const std::string table = markdown_table(records);
  EXPECT_NE(table.find("1.00×"), std::string::npos) << table;
}

TEST(BenchCsmSuite, HostRowsOfLaterDevicesAreNotRecordedAgain) {
  if (const std::string missing = missing_bench_model("csm"); !missing.empty()) GTEST_SKIP() << missing << " not found";
  SessionOptions options;
  options.quick = true;
  options.measure = MeasureOptions{0, 1};
  options.measure_host = false;
  Session session("csm", options);
  run_csm_suite(session);
  for (const Record& r : session.records()) EXPECT_EQ(r.impl, kImplOpenCL) << r.case_name;
  // capture (raycast, raster), compress, visibility (kernel only, with host I/O), ao, stream-copy, peak-fma
  EXPECT_EQ(session.records().size(), 8u);
}

}  // namespace
}  // namespace splatcl::bench
