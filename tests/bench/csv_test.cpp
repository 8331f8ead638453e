// Benchmark records through JSON and CSV files and back: every fixed field and every kind of extra
// field survives both formats unchanged.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "bench/csv.hpp"
#include "bench/record.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

Results sample_results() {
  Results results;
  results.machine = Json{{"cpu_model", "Test CPU"}, {"logical_cores", 2}};
  Record a;
  a.suite = "csm";
  a.case_name = "capture";
  a.impl = kImplOpenCL;
  a.device = "pthread-test, with \"quotes\"";
  a.size = 1048576;
  a.size_unit = "rays";
  a.runs = 7;
  a.median_ms = 123.456789012345;
  a.min_ms = 1e-7;  // far from 1 either way: the CSV keeps every digit (and min <= median <= max, as a record must)
  a.max_ms = 1234567.0001;
  a.throughput = 8.493e6 / 3.0;
  a.throughput_unit = "rays/s";
  a.peak_rss_mb = 412.75;
  a.extra = Json{{"model", "stanford-bunny"}, {"res", 128}, {"shape", "cpu"}, {"device_ms", {{"csm capture", 120.5}}},
                 {"device_total_ms", 120.5}};
  Record b;
  b.suite = "csm";
  b.case_name = "capture";
  b.impl = "embree";
  b.device = kHostDevice;
  b.runs = 1;
  b.median_ms = 2;
  b.min_ms = 2;
  b.max_ms = 2;
  b.extra = Json{{"variant", "rtcIntersect16, 3.13.5\nline two"}, {"rays_cast", {{"first", 10}, {"second", 4}}}, {"flag", true}};
  results.records = {a, b};
  return results;
}

void expect_same_records(const Results& actual, const Results& expected) {
  ASSERT_EQ(actual.records.size(), expected.records.size());
  for (std::size_t k = 0; k < actual.records.size(); ++k)
    EXPECT_EQ(to_json(actual.records[k]), to_json(expected.records[k])) << "record " << k;
}

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("splatcl-csv-test-" + std::to_string(::getpid()) + "-" + name);
}

TEST(BenchCsv, JsonFileRoundTrip) {
  const Results results = sample_results();
  const fs::path path = scratch("results.json");
  write_results(path.string(), results);
  const Results back = read_results(path.string());
  fs::remove(path);
  expect_same_records(back, results);
  EXPECT_EQ(back.machine, results.machine);
}

TEST(BenchCsv, CsvFileRoundTrip) {
  const Results results = sample_results();
  const fs::path path = scratch("results.csv");
  write_csv(path.string(), results);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("suite,case,impl,device,size,size_unit,runs,median_ms,min_ms,max_ms,throughput,throughput_unit,peak_rss_mb,", 0), 0u)
      << header;
  in.close();
  const Results back = read_csv(path.string());
  fs::remove(path);
  expect_same_records(back, results);
}

// A spreadsheet saves CSV with a UTF-8 byte-order mark: read as without it (it was refused as
// "not a benchmark CSV").
TEST(BenchCsv, AByteOrderMarkIsSkipped) {
  const Results results = sample_results();
  expect_same_records(results_from_csv("\xEF\xBB\xBF" + to_csv(results)), results);
}

TEST(BenchCsv, EmptyResultsHaveOnlyTheHeader) {
  const Results back = results_from_csv(to_csv(Results{}));
  EXPECT_TRUE(back.records.empty());
}

TEST(BenchCsv, BadFilesAreErrorsNamingTheProblem) {
  EXPECT_THROW(results_from_csv(""), Error);
  EXPECT_THROW(results_from_csv("a,b,c\n1,2,3\n"), Error);
  const std::string header = to_csv(Results{});
  try {
    results_from_csv(header + "csm,capture,opencl,dev,12,rays,seven,1,1,1,,,\n");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("runs"), std::string::npos) << e.what();
  }
  EXPECT_THROW(results_from_csv(header + "csm,capture\n"), Error);                         // short row
  EXPECT_THROW(results_from_csv(header + "\"csm,capture,opencl,dev,1,r,1,1,1,1,,,\n"), Error);  // open quote
  EXPECT_THROW(read_csv("/nonexistent/results.csv"), Error);
  // A fuzz finding (tests/fuzz/corpus/bench_csv/regression-not-utf8.csv): text the JSON reader
  // refuses, and --json could not write.
  try {
    results_from_csv(header + "csm,capt\xDF\xFFre,opencl,dev,12,rays,7,1,1,1,,,\n");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "not UTF-8 text");
  }
  // A fuzz finding (regression-runs-beyond-int.csv): a run count beyond int was cast (UB).
  try {
    results_from_csv(header + "csm,capture,opencl,dev,12,rays,3333333333333,1,1,1,,,\n");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'runs' is not a positive integer"), std::string::npos) << e.what();
  }
  // A column named twice (a helper's audit: the later cell won, or a fixed column's repeat read as
  // "times must be finite ...").
  std::string twice = header;
  twice.insert(twice.find('\n'), ",note,note");
  try {
    results_from_csv(twice);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "column 'note' appears twice in the header");
  }
}

}  // namespace
}  // namespace splatcl::bench
