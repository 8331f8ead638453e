#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "bench/record.hpp"
#include "bench/session.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

SessionOptions quick_options(const std::string& json_path = "") {
  SessionOptions options;
  options.measure = MeasureOptions{1, 3};
  options.json_path = json_path;
  return options;
}

TEST(BenchSession, HostRowGetsSummaryThroughputAndPeak) {
  Session session("test", quick_options());
  int runs = 0;
  const Record& r = session.measure(reference_case("sum", 1000, "keys", Json{{"bits", 20}}), {}, [&] { ++runs; });
  EXPECT_EQ(runs, 4);  // warm-up + timed
  EXPECT_EQ(r.suite, "test");
  EXPECT_EQ(r.case_name, "sum");
  EXPECT_EQ(r.impl, kImplReference);
  EXPECT_EQ(r.device, kHostDevice);
  EXPECT_EQ(r.runs, 3);
  EXPECT_LE(r.min_ms, r.median_ms);
  EXPECT_LE(r.median_ms, r.max_ms);
  ASSERT_TRUE(r.size.has_value());
  EXPECT_EQ(*r.size, 1000u);
  EXPECT_EQ(r.size_unit, "keys");
  if (r.median_ms > 0) {
    ASSERT_TRUE(r.throughput.has_value());
    EXPECT_DOUBLE_EQ(*r.throughput, 1000.0 / (r.median_ms * 1e-3));
    EXPECT_EQ(r.throughput_unit, "keys/s");
  }
  EXPECT_EQ(r.extra["bits"], 20);
  EXPECT_FALSE(r.extra.contains("device_ms"));  // no profiler
}

TEST(BenchSession, OpenCLRowRecordsShapeDeviceAndKernelTimes) {
  Session session("test", quick_options());
  Runtime& runtime = session.runtime();
  const std::size_t vectors = 1024;
  cl::Buffer src = runtime.buffer(CL_MEM_READ_WRITE, vectors * sizeof(cl_uint4), "test source");
  cl::Buffer dst = runtime.buffer(CL_MEM_READ_WRITE, vectors * sizeof(cl_uint4), "test destination");
  cl::Kernel kernel = runtime.kernel("bench.cl", "copy_uint4");
  kernel.setArg(0, src);
  kernel.setArg(1, dst);
  Profiler profiler;
  const Case c = opencl_case("copy", Shape::Cpu, vectors, "vectors", {}, Json{{"variant", "plain"}});
  EXPECT_EQ(describe(c), "copy opencl plain (cpu shape)");
  const Record& r = session.measure(c, {}, [&] {
    enqueue_1d(runtime.queue(), kernel, vectors, 0, &profiler, "copy_uint4");
    runtime.queue().finish();
  }, &profiler);
  EXPECT_EQ(r.device, runtime.info().name);
  EXPECT_EQ(r.extra["shape"], "cpu");
  EXPECT_EQ(r.extra["variant"], "plain");
  ASSERT_TRUE(r.extra.contains("device_ms"));
  EXPECT_TRUE(r.extra["device_ms"].contains("copy_uint4"));
  EXPECT_GE(r.extra["device_total_ms"].get<double>(), 0.0);
}

// The machine block says how the results were taken: the command, how busy the machine was,
// quick or not, and whether the tuning database has a record for the device at all.
TEST(BenchSession, MachineBlockNamesTheCommandLoadQuickAndTuning) {
  Session session("test", quick_options());
  const Json machine = session.results().machine;
  EXPECT_NE(machine.at("command").get<std::string>().find("splatcl_tests_bench"), std::string::npos) << machine.dump();
  ASSERT_TRUE(machine.at("load_average").is_array());
  EXPECT_EQ(machine.at("load_average").size(), 3u);
  EXPECT_GE(machine.at("load_average")[0].get<double>(), 0.0);
  EXPECT_FALSE(machine.at("quick").get<bool>());
  const std::string tuning = machine.at("tuning").get<std::string>();
  EXPECT_EQ(tuning.rfind("embedded data/tuning.json", 0), 0u) << tuning;
}

// A shape whose kernel writes nothing must fail its check: the output buffer, shared between the
// two shapes, holds no earlier shape's result once poisoned.
TEST(BenchSession, PoisonedOutputFailsTheCheckOfAShapeThatWritesNothing) {
  Session session("test", quick_options());
  Runtime& runtime = session.runtime();
  const std::vector<std::uint32_t> expected(257, 7u);
  const cl::Buffer out = upload(runtime, expected, "test output");
  EXPECT_NO_THROW(expect_same_output("first shape", download<std::uint32_t>(runtime, out, expected.size()), expected));
  poison_buffer(runtime, out, expected.size() * sizeof(std::uint32_t));
  const std::vector<std::uint32_t> left = download<std::uint32_t>(runtime, out, expected.size());
  EXPECT_EQ(std::count(left.begin(), left.end(), 0xA5A5A5A5u), 257);
  EXPECT_THROW(expect_same_output("second shape", left, expected), Error);
}

TEST(BenchSession, FinishPrintsTheTableAndWritesTheFile) {
  const fs::path dir = fs::temp_directory_path() / "splatcl_bench_session";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "out.json").string();
  Session session("test", quick_options(path));
  session.measure(reference_case("noop", 10, "keys"), {}, [] {});
  testing::internal::CaptureStdout();
  session.finish();
  const std::string printed = testing::internal::GetCapturedStdout();
  EXPECT_NE(printed.find("### test"), std::string::npos) << printed;
  EXPECT_NE(printed.find("| noop "), std::string::npos) << printed;
  const Results written = read_results(path);
  ASSERT_EQ(written.records.size(), 1u);
  EXPECT_EQ(written.records[0].case_name, "noop");
  EXPECT_EQ(written.machine["opencl_device"], session.runtime().info().name);
}

TEST(BenchSession, AWithdrawnRowLeavesTheOthers) {
  Session session("test", quick_options());
  session.measure(reference_case("kept", 10, "keys"), {}, [] {});
  session.measure(reference_case("wrong", 10, "keys"), {}, [] {});
  testing::internal::CaptureStderr();
  session.withdraw_last_record("bench wrong: output differs from the reference at index 3");
  const std::string warning = testing::internal::GetCapturedStderr();
  ASSERT_EQ(session.records().size(), 1u);
  EXPECT_EQ(session.records()[0].case_name, "kept");
  EXPECT_NE(warning.find("warning: bench wrong: output differs from the reference at index 3; that row is left out"),
            std::string::npos);
}

TEST(BenchSession, MissingOutputDirectoryFailsBeforeMeasuring) {
  EXPECT_THROW(Session("test", quick_options("/nonexistent-splatcl-dir/out.json")), Error);
}

}  // namespace
}  // namespace splatcl::bench
