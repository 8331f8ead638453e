// bench tune (bench/tune.hpp) on the default device: records for the device, parameters from the
// search space, measurements filled in, and a database that reads back to the same records.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "bench/tune.hpp"
#include "runtime/error.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::bench {
namespace {

TEST(BenchTune, QuickScanTuningWritesARecordForTheDevice) {
  const DeviceInfo device = choose_device();
  TuneOptions options;
  options.devices = {std::to_string(device.index)};
  options.kernels = {"scan"};
  options.shapes = {Shape::Cpu};  // no kernel builds beyond the default program: seconds, not minutes
  options.quick = true;
  options.measure = {1, 2};
  const auto results = run_tuning(options);
  ASSERT_EQ(results.size(), 1u);
  const TuneResult& r = results[0];
  EXPECT_EQ(r.record.kernel, "scan");
  EXPECT_EQ(r.record.shape, "cpu");
  EXPECT_EQ(r.record.vendor, device.vendor);
  EXPECT_EQ(r.record.device_name, device.name);
  EXPECT_EQ(r.record.device_type, device.type);
  EXPECT_TRUE(r.record.matches(device));
  ASSERT_EQ(r.record.parameters.size(), 2u);
  EXPECT_EQ(r.record.parameters.at("chunks_per_compute_unit"), r.best.chunks_per_compute_unit);
  EXPECT_EQ(r.record.parameters.at("min_chunk_items"), r.best.min_chunk_items);
  EXPECT_EQ(r.defaults, primitives::LaunchParameters{});
  // The defaults, then 5 more chunk counts and 2 more minimum chunk sizes.
  EXPECT_EQ(r.candidates, 8);
  EXPECT_EQ(r.refused, 0);
  EXPECT_GT(r.default_ms, 0);
  EXPECT_GT(r.best_ms, 0);
  EXPECT_LE(r.best_ms, r.default_ms);  // a candidate that loses the side-by-side runs is not kept
  if (r.best == r.defaults) {
    EXPECT_EQ(r.best_ms, r.default_ms);
  }
  EXPECT_EQ(r.record.measured.at("size").get<int>(), 1 << 16);
  EXPECT_DOUBLE_EQ(r.record.measured.at("gain").get<double>(), r.default_ms / r.best_ms);

  const std::string report = tuning_report(results);
  EXPECT_NE(report.find("| scan | cpu | " + device.name + " | chunks_per_compute_unit="), std::string::npos) << report;

  TuningDatabase database;
  database.put(r.record);
  database.put(r.record);  // the same kernel, shape and device: replaced, not added
  const auto path = (std::filesystem::temp_directory_path() / ("splatcl-tune-test-" + std::to_string(::getpid()) + ".json")).string();
  database.write(path);
  const TuningDatabase back = TuningDatabase::read(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.records().size(), 1u);
  const TuningRecord* found = back.find("scan", "cpu", device);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->parameters, r.record.parameters);
  EXPECT_EQ(back.find("scan", "gpu", device), nullptr);
}

TEST(BenchTune, UnknownKernelIsAnError) {
  EXPECT_THROW(parse_tuned_kernel("fft"), Error);
  try {
    parse_tuned_kernel("fft");
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown kernel 'fft' to tune (one of: scan, compact, radix-sort)");
  }
}

}  // namespace
}  // namespace splatcl::bench
