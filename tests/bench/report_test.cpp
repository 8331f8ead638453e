#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "bench/record.hpp"
#include "bench/report.hpp"

namespace splatcl::bench {
namespace {

const char* const kResults = R"({
  "machine": {"cpu_model": "Test CPU 9000", "logical_cores": 2, "memory_gib": 23.4,
              "opencl_device": "pthread-test", "opencl_device_version": "OpenCL 3.0 PoCL 3.1",
              "pocl_max_pthread_count": "2", "date": "2024-01-01T00:00:00Z"},
  "records": [
    {"suite": "primitives", "case": "radix-sort-u32", "impl": "opencl", "device": "pthread-test",
     "size": 1000, "size_unit": "keys", "runs": 7, "median_ms": 5, "min_ms": 4, "max_ms": 6,
     "throughput": 200000, "throughput_unit": "keys/s", "peak_rss_mb": 100, "bits": 20, "shape": "cpu"},
    {"suite": "primitives", "case": "radix-sort-u32", "impl": "reference", "device": "host",
     "size": 1000, "size_unit": "keys", "runs": 7, "median_ms": 10, "min_ms": 9, "max_ms": 11, "bits": 20},
    {"suite": "primitives", "case": "radix-sort-u32", "impl": "opencl", "device": "pthread-test",
     "size": 1000, "size_unit": "keys", "runs": 7, "median_ms": 8, "min_ms": 8, "max_ms": 8, "bits": 32,
     "shape": "cpu"},
    {"suite": "primitives", "case": "stream-copy", "impl": "std::thread copy loop", "device": "host",
     "size": 2000000000, "size_unit": "bytes", "runs": 3, "median_ms": 100, "min_ms": 90, "max_ms": 110,
     "throughput": 2.0e10, "throughput_unit": "bytes/s", "threads": 2},
    {"suite": "primitives", "case": "stream-copy", "impl": "opencl", "device": "pthread-test",
     "size": 2000000000, "size_unit": "bytes", "runs": 3, "median_ms": 80, "min_ms": 79, "max_ms": 81,
     "throughput": 2.5e10, "throughput_unit": "bytes/s", "device_ms": {"copy_uint4": 79.5}}
  ]})";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The table row whose cells start with `case_cell` and `impl_cell`.
std::string row(const std::string& report, const std::string& case_cell, const std::string& impl_cell) {
  for (const auto& line : lines_of(report)) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, '|');) {
      const auto begin = cell.find_first_not_of(' ');
      const auto end = cell.find_last_not_of(' ');
      cells.push_back(begin == std::string::npos ? "" : cell.substr(begin, end - begin + 1));
    }
    if (cells.size() > 2 && cells[1] == case_cell && cells[2] == impl_cell) return line;
  }
  return {};
}

TEST(BenchReport, RendersMachineLineHeadingAndTable) {
  const std::string report = markdown_report(results_from_json(Json::parse(kResults)));
  const auto lines = lines_of(report);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0].rfind("**Machine:** Test CPU 9000 (2 logical cores, 23.4 GiB)", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find("OpenCL device pthread-test (OpenCL 3.0 PoCL 3.1)"), std::string::npos);
  EXPECT_NE(lines[0].find("POCL_MAX_PTHREAD_COUNT=2"), std::string::npos);
  EXPECT_NE(report.find("### primitives"), std::string::npos);
  EXPECT_NE(report.find("| case "), std::string::npos);
  EXPECT_NE(report.find("median ms"), std::string::npos);
  // Header, alignment row and one row per record; every row has the same number of cells.
  std::size_t table_lines = 0;
  for (const auto& line : lines)
    if (line.rfind("|", 0) == 0) {
      ++table_lines;
      // 9 columns plus "vs peer" (the stream-copy rows have peers).
      EXPECT_EQ(std::count(line.begin(), line.end(), '|'), 11) << line;
    }
  EXPECT_EQ(table_lines, 2u + 5u);
}

TEST(BenchReport, ComparesWithTheReferenceOfTheSameVariantOnly) {
  const std::string report = markdown_report(results_from_json(Json::parse(kResults)));
  const std::string fast = row(report, "radix-sort-u32 bits=20", "opencl (cpu shape)");
  ASSERT_FALSE(fast.empty()) << report;
  EXPECT_NE(fast.find("2.00×"), std::string::npos) << fast;
  EXPECT_NE(fast.find("200.0 k keys/s"), std::string::npos) << fast;
  EXPECT_NE(fast.find(" 5.00 | "), std::string::npos) << fast;
  const std::string reference = row(report, "radix-sort-u32 bits=20", "reference");
  EXPECT_NE(reference.find("1.00×"), std::string::npos) << reference;
  // bits=32 has no reference and no peer: no speedup.
  const std::string alone = row(report, "radix-sort-u32 bits=32", "opencl (cpu shape)");
  ASSERT_FALSE(alone.empty()) << report;
  EXPECT_NE(alone.find("—"), std::string::npos) << alone;
}

TEST(BenchReport, WithoutAReferenceThePeerIsTheBaseline) {
  const std::string report = markdown_report(results_from_json(Json::parse(kResults)));
  // "threads" and "device_ms" describe how a row ran, so both rows share the case "stream-copy".
  const std::string copy = row(report, "stream-copy", "opencl");
  ASSERT_FALSE(copy.empty()) << report;
  EXPECT_NE(copy.find("1.25×"), std::string::npos) << copy;
  EXPECT_NE(copy.find("25.0 GB/s"), std::string::npos) << copy;
  EXPECT_NE(row(report, "stream-copy", "std::thread copy loop").find("20.0 GB/s"), std::string::npos);
}

// A case's counted flops per run against the same device's peak-fma throughput; other devices' peak
// does not count, and a device without a peak-fma row shows none.
TEST(BenchReport, ShareOfPeakArithmeticUsesTheSameDevicesFmaRow) {
  const Results results = results_from_json(Json::parse(R"({"machine": {}, "records": [
    {"suite": "cluster", "case": "assign-lights", "impl": "opencl", "device": "dev-a", "size": 10, "size_unit": "clusters",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "variant": "brute", "flops": 2.5e8},
    {"suite": "cluster", "case": "assign-lights", "impl": "opencl", "device": "dev-b", "size": 10, "size_unit": "clusters",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "variant": "brute", "flops": 2.5e8},
    {"suite": "cluster", "case": "peak-fma", "impl": "opencl", "device": "dev-a", "size": 1000000000, "size_unit": "flop",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "throughput": 1e11, "throughput_unit": "flop/s"},
    {"suite": "cluster", "case": "peak-fma", "impl": "opencl", "device": "dev-b", "size": 1000000000, "size_unit": "flop",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10}]})"));
  const std::string table = markdown_table(results.records);
  EXPECT_NE(table.find("of peak FLOP/s"), std::string::npos) << table;
  std::vector<std::string> brute_rows;
  for (const auto& line : lines_of(table))
    if (line.find("assign-lights") != std::string::npos) brute_rows.push_back(line);
  ASSERT_EQ(brute_rows.size(), 2u) << table;
  // 2.5e8 flop in 10 ms = 25 GFLOP/s, 25 % of dev-a's 100 GFLOP/s; dev-b's peak row has no throughput.
  EXPECT_NE(brute_rows[0].find("| dev-a "), std::string::npos) << brute_rows[0];
  EXPECT_NE(brute_rows[0].find(" 25 % |"), std::string::npos) << brute_rows[0];
  EXPECT_EQ(brute_rows[1].find(" % |"), std::string::npos) << brute_rows[1];
  // The case is the same on both devices: the flops field does not make a variant of it.
  EXPECT_EQ(case_label(results.records[0]), "assign-lights");
}

// In a run of several suites each measures its own peak: a record is set against its own suite's
// row, not the first of any suite (the cluster rows read 25 % of the primitives suite's peak where
// their own suite's gave 40 %).
TEST(BenchReport, ShareOfPeakArithmeticUsesTheSameSuitesFmaRow) {
  const Results results = results_from_json(Json::parse(R"({"machine": {}, "records": [
    {"suite": "primitives", "case": "peak-fma", "impl": "opencl", "device": "dev-a", "size": 1000000000, "size_unit": "flop",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "throughput": 1e11, "throughput_unit": "flop/s"},
    {"suite": "cluster", "case": "assign-lights", "impl": "opencl", "device": "dev-a", "size": 10, "size_unit": "clusters",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "variant": "brute", "flops": 2.5e8},
    {"suite": "cluster", "case": "peak-fma", "impl": "opencl", "device": "dev-a", "size": 1000000000, "size_unit": "flop",
     "runs": 1, "median_ms": 10, "min_ms": 10, "max_ms": 10, "throughput": 5e10, "throughput_unit": "flop/s"}]})"));
  std::string brute;
  for (const auto& line : lines_of(markdown_table(results.records)))
    if (line.find("assign-lights") != std::string::npos) brute = line;
  // 25 GFLOP/s against the cluster suite's 50: 50 %, not 25 % of the primitives suite's 100.
  EXPECT_NE(brute.find(" 50 % |"), std::string::npos) << brute;
}

TEST(BenchReport, ImplementationVariantsShareTheCaseAndItsReference) {
  Results results;
  Record bitmask;
  bitmask.suite = "cluster";
  bitmask.case_name = "compact";
  bitmask.impl = kImplOpenCL;
  bitmask.device = "dev";
  bitmask.runs = 1;
  bitmask.median_ms = bitmask.min_ms = bitmask.max_ms = 4;
  bitmask.extra = Json{{"variant", "bitmask"}, {"shape", "gpu"}};
  Record reference = bitmask;
  reference.impl = kImplReference;
  reference.median_ms = reference.min_ms = reference.max_ms = 12;
  reference.extra = Json::object();
  results.records = {bitmask, reference};
  const std::string table = markdown_table(results.records);
  const std::string row_text = row(table, "compact", "opencl bitmask (gpu shape)");
  ASSERT_FALSE(row_text.empty()) << table;
  EXPECT_NE(row_text.find("3.00×"), std::string::npos) << row_text;
}

TEST(BenchReport, MachineLineSaysWhenNothingWasRecorded) {
  EXPECT_EQ(machine_line(Json::object()), "**Machine:** not recorded\n");
}

}  // namespace
}  // namespace splatcl::bench
