#include <gtest/gtest.h>

#include <tuple>

#include <filesystem>
#include <fstream>

#include "bench/record.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

Record full_record() {
  Record r;
  r.suite = "primitives";
  r.case_name = "radix-sort-u32";
  r.impl = kImplOpenCL;
  r.device = "pthread-test-device";
  r.size = 2073600;
  r.size_unit = "keys";
  r.runs = 7;
  r.median_ms = 12.5;
  r.min_ms = 11.0;
  r.max_ms = 14.25;
  r.throughput = 1.65888e8;
  r.throughput_unit = "keys/s";
  r.peak_rss_mb = 321.5;
  r.extra = Json{{"bits", 20}, {"shape", "cpu"}, {"device_ms", {{"histogram", 1.5}, {"scatter", 3.0}}}};
  return r;
}

// A record where size, throughput and peak RSS do not apply.
Record minimal_record() {
  Record r;
  r.suite = "cluster";
  r.case_name = "assign-lights";
  r.impl = kImplReference;
  r.device = kHostDevice;
  r.runs = 3;
  r.median_ms = 2;
  r.min_ms = 1;
  r.max_ms = 3;
  return r;
}

TEST(BenchRecord, JsonHasTheFormatFieldsInOrderThenExtras) {
  const Json json = to_json(full_record());
  std::vector<std::string> keys;
  for (const auto& [key, value] : json.items()) keys.push_back(key);
  const std::vector<std::string> expected = {"suite",  "case",       "impl",          "device",          "size",
                                             "size_unit", "runs",    "median_ms",     "min_ms",          "max_ms",
                                             "throughput", "throughput_unit", "peak_rss_mb", "bits", "shape",
                                             "device_ms"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(json["case"], "radix-sort-u32");
  EXPECT_EQ(json["size"], 2073600u);
  EXPECT_EQ(json["device_ms"]["scatter"], 3.0);
}

TEST(BenchRecord, InapplicableFieldsAreLeftOut) {
  const Json json = to_json(minimal_record());
  for (const char* absent : {"size", "size_unit", "throughput", "throughput_unit", "peak_rss_mb"})
    EXPECT_FALSE(json.contains(absent)) << absent;
  for (const char* present : {"suite", "case", "impl", "device", "runs", "median_ms", "min_ms", "max_ms"})
    EXPECT_TRUE(json.contains(present)) << present;
}

TEST(BenchRecord, RoundTripsThroughJsonText) {
  for (const Record& original : {full_record(), minimal_record()}) {
    const Record back = record_from_json(Json::parse(to_json(original).dump()));
    EXPECT_EQ(back.suite, original.suite);
    EXPECT_EQ(back.case_name, original.case_name);
    EXPECT_EQ(back.impl, original.impl);
    EXPECT_EQ(back.device, original.device);
    EXPECT_EQ(back.size, original.size);
    EXPECT_EQ(back.size_unit, original.size_unit);
    EXPECT_EQ(back.runs, original.runs);
    EXPECT_DOUBLE_EQ(back.median_ms, original.median_ms);
    EXPECT_DOUBLE_EQ(back.min_ms, original.min_ms);
    EXPECT_DOUBLE_EQ(back.max_ms, original.max_ms);
    EXPECT_EQ(back.throughput, original.throughput);
    EXPECT_EQ(back.throughput_unit, original.throughput_unit);
    EXPECT_EQ(back.peak_rss_mb, original.peak_rss_mb);
    EXPECT_EQ(back.extra, original.extra);
  }
}

TEST(BenchRecord, MissingOrMistypedRequiredFieldIsAnError) {
  Json json = to_json(full_record());
  json.erase("median_ms");
  EXPECT_THROW(record_from_json(json), Error);
  json = to_json(full_record());
  json["runs"] = "seven";
  EXPECT_THROW(record_from_json(json), Error);
  json = to_json(full_record());
  json["size"] = -1;
  EXPECT_THROW(record_from_json(json), Error);
  // Times no run can take (report printed them; compare read +0.0 % against a median of 0 or -1).
  for (const auto& [min_ms, median_ms, max_ms] : {std::tuple{-1.0, -1.0, -1.0}, std::tuple{0.0, 0.0, 0.0}, std::tuple{2.0, 1.0, 3.0},
                                                  std::tuple{1.0, 3.0, 2.0}}) {
    json = to_json(full_record());
    json["min_ms"] = min_ms, json["median_ms"] = median_ms, json["max_ms"] = max_ms;
    EXPECT_THROW(record_from_json(json), Error) << min_ms << " / " << median_ms << " / " << max_ms;
  }
}

TEST(BenchRecord, ExtraFieldMayNotShadowAFixedOne) {
  Record r = minimal_record();
  r.extra["median_ms"] = 1.0;
  EXPECT_THROW(to_json(r), Error);
}

TEST(BenchRecord, ResultsFileRoundTrips) {
  const fs::path dir = fs::temp_directory_path() / "splatcl_bench_results";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Results results;
  results.machine = machine_info(nullptr);
  results.records = {full_record(), minimal_record()};
  const std::string path = (dir / "results.json").string();
  write_results(path, results);
  const Results back = read_results(path);
  EXPECT_EQ(back.machine, results.machine);
  ASSERT_EQ(back.records.size(), 2u);
  EXPECT_EQ(to_json(back.records[0]), to_json(results.records[0]));
  EXPECT_EQ(to_json(back.records[1]), to_json(results.records[1]));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temporary left
}

TEST(BenchRecord, WriteIntoMissingDirectoryIsAClearErrorAndLeavesNothing) {
  const fs::path dir = fs::temp_directory_path() / "splatcl_bench_no_such_dir";
  fs::remove_all(dir);
  const std::string path = (dir / "results.json").string();
  Results results;
  results.records = {minimal_record()};
  try {
    write_results(path, results);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir));
}

TEST(BenchRecord, ReadingAMissingOrForeignFileIsAClearError) {
  EXPECT_THROW(read_results("/nonexistent-splatcl/results.json"), Error);
  const fs::path path = fs::temp_directory_path() / "splatcl_bench_foreign.json";
  std::ofstream(path) << R"({"something": "else"})";
  try {
    read_results(path.string());
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  std::ofstream(path) << "{ not json";
  EXPECT_THROW(read_results(path.string()), Error);
  // A top-level key it does not know, or a key twice (the later won silently).
  const auto message_of = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      read_results(path.string());
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message_of(R"({"machine": {}, "records": [], "note": 1})"),
            path.string() + ": unknown top-level key 'note' (known: machine, records)");
  EXPECT_EQ(message_of(R"({"machine": {"hostname": "a", "hostname": "b"}, "records": []})"),
            path.string() + ": machine: key 'hostname' appears twice in one object");
  fs::remove(path);
}

TEST(BenchRecord, MachineInfoDescribesTheHost) {
  const Json machine = machine_info(nullptr);
  for (const char* key : {"hostname", "cpu_model", "logical_cores", "os", "compiler", "build", "date"})
    EXPECT_TRUE(machine.contains(key)) << key;
  EXPECT_GE(machine["logical_cores"].get<int>(), 1);
  EXPECT_FALSE(machine.contains("opencl_device"));  // no device given
}

}  // namespace
}  // namespace splatcl::bench
