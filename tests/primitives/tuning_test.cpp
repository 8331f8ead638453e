// Tuning records (runtime/tuning.hpp, primitives/tuning.hpp): lookup by device, defaults when no
// record matches, refusal of values the device or the kernels cannot take, and the kernels with
// non-default parameters equal to the references.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"
#include "primitives/tuning.hpp"
#include "primitives_test_support.hpp"
#include "runtime/error.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::primitives::testing {
namespace {

DeviceInfo device(const std::string& vendor, const std::string& name, const std::string& type) {
  DeviceInfo info;
  info.vendor = vendor;
  info.name = name;
  info.type = type;
  info.max_work_group_size = 1024;
  info.local_mem_bytes = 48 * 1024;
  return info;
}

std::string expect_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(Tuning, TheMostSpecificMatchingRecordWins) {
  const auto database = TuningDatabase::parse(R"({"records": [
      {"kernel": "scan", "shape": "gpu", "device": {"type": "gpu"}, "parameters": {"group_size": 64}},
      {"kernel": "scan", "shape": "gpu", "device": {"vendor": "NVIDIA Corporation", "type": "gpu"}, "parameters": {"group_size": 128}},
      {"kernel": "scan", "shape": "gpu", "device": {"vendor": "NVIDIA Corporation", "name": "NVIDIA H200", "type": "gpu"},
       "parameters": {"group_size": 512}},
      {"kernel": "scan", "shape": "cpu", "device": {"type": "gpu"}, "parameters": {"min_chunk_items": 7}}]})",
                                              "test database");
  const auto* h200 = database.find("scan", "gpu", device("NVIDIA Corporation", "NVIDIA H200", "gpu"));
  ASSERT_NE(h200, nullptr);
  EXPECT_EQ(h200->parameters.at("group_size"), 512);
  const auto* other_nvidia = database.find("scan", "gpu", device("NVIDIA Corporation", "NVIDIA A100", "gpu"));
  ASSERT_NE(other_nvidia, nullptr);
  EXPECT_EQ(other_nvidia->parameters.at("group_size"), 128);
  const auto* any_gpu = database.find("scan", "gpu", device("Advanced Micro Devices, Inc.", "gfx90a", "gpu"));
  ASSERT_NE(any_gpu, nullptr);
  EXPECT_EQ(any_gpu->parameters.at("group_size"), 64);
  EXPECT_EQ(database.find("scan", "gpu", device("AuthenticAMD", "pthread-znver4", "cpu")), nullptr);
  EXPECT_EQ(database.find("compact", "gpu", device("NVIDIA Corporation", "NVIDIA H200", "gpu")), nullptr);
}

TEST(Tuning, NoRecordGivesTheDefaultsAndARecordOnlyWhatItSets) {
  TuningRecord record;
  record.kernel = "radix-sort";
  record.shape = "cpu";
  record.parameters = {{"digit_bits", 10}};
  const LaunchParameters applied = apply_record(record, Primitive::RadixSort, Shape::Cpu, "test");
  LaunchParameters expected;
  expected.digit_bits = 10;
  EXPECT_EQ(applied, expected);
  EXPECT_EQ(apply_record(TuningRecord{}, Primitive::Scan, Shape::Gpu, "test"), LaunchParameters{});
}

TEST(Tuning, MalformedDatabasesAreErrorsNamingTheSource) {
  EXPECT_EQ(expect_error([] { TuningDatabase::parse("{", "t.json"); }).rfind("t.json: not valid JSON", 0), 0u);
  EXPECT_EQ(expect_error([] { TuningDatabase::parse(R"({"recs": []})", "t.json"); }),
            "t.json: not a tuning database (no \"records\" array)");
  EXPECT_EQ(expect_error([] {
              TuningDatabase::parse(R"({"records": [{"kernel": "scan", "shape": "gpu", "parameters": {"group_size": "big"}}]})",
                                    "t.json");
            }),
            "t.json: records[0]: parameter 'group_size' must be an integer");
  EXPECT_EQ(expect_error([] {
              TuningDatabase::parse(R"({"records": [{"kernel": "scan", "shape": "simd", "parameters": {}}]})", "t.json");
            }),
            "t.json: records[0]: 'shape' must be \"cpu\" or \"gpu\"");
  // A key or a record given twice: the later won silently.
  EXPECT_EQ(expect_error([] {
              TuningDatabase::parse(R"({"records": [{"kernel": "scan", "shape": "cpu", "shape": "gpu", "parameters": {}}]})", "t.json");
            }),
            "t.json: records[0]: key 'shape' appears twice in one object");
  EXPECT_EQ(expect_error([] {
              TuningDatabase::parse(R"({"records": [{"kernel": "scan", "shape": "cpu", "parameters": {"min_chunk_items": 64}},
                                                    {"kernel": "scan", "shape": "cpu", "parameters": {"min_chunk_items": 32}}]})",
                                    "t.json");
            }),
            "t.json: records[1]: the same kernel, shape and devices as an earlier record");
  // Inside 'measured' too (the record's other objects were closed already).
  EXPECT_EQ(expect_error([] {
              TuningDatabase::parse(R"({"records": [{"kernel": "scan", "shape": "cpu", "parameters": {}, "measured": {"gian": 2}}]})", "t.json");
            }),
            "t.json: records[0]: unknown measured key 'gian' (known: size, size_unit, default_ms, tuned_ms, gain, candidates, date)");
  TuningRecord record;
  record.kernel = "scan";
  record.shape = "cpu";
  record.parameters = {{"digit_bits", 10}};
  EXPECT_EQ(expect_error([&] { apply_record(record, Primitive::Scan, Shape::Cpu, "t.json"); }),
            "t.json: scan (cpu shape) has no parameter 'digit_bits' (known: chunks_per_compute_unit, min_chunk_items)");
}

TEST(Tuning, ValuesBeyondTheDeviceOrTheKernelsAreRefused) {
  const DeviceInfo gpu = device("NVIDIA Corporation", "NVIDIA H200", "gpu");
  LaunchParameters p;
  p.group_size = 2048;
  EXPECT_EQ(expect_error([&] { validate(p, Primitive::Scan, Shape::Gpu, gpu); }),
            "tuning of scan: group_size = 2048 exceeds the 1024 work-items per group of 'NVIDIA H200'");
  p.group_size = 100;
  EXPECT_EQ(expect_error([&] { validate(p, Primitive::Compact, Shape::Gpu, gpu); }),
            "tuning of compact: group_size = 100 must be a positive multiple of 16 (the group scan's rakes)");
  // 1024 x 8 keys of 8 bytes with values: 132 KiB of local memory, beyond 48 KiB.
  p.group_size = 1024;
  p.items_per_work_item = 8;
  const std::string local = expect_error([&] { validate(p, Primitive::RadixSort, Shape::Gpu, gpu, 8, true); });
  EXPECT_NE(local.find("B of local memory, more than the 49152 B of 'NVIDIA H200'"), std::string::npos) << local;
  // Within 48 KiB: 256 x 4 keys of 8 bytes with values.
  p.group_size = 256;
  p.items_per_work_item = 4;
  EXPECT_LE(gpu_local_bytes(p, Primitive::RadixSort, 8, true), gpu.local_mem_bytes);
  EXPECT_NO_THROW(validate(p, Primitive::RadixSort, Shape::Gpu, gpu, 8, true));
  LaunchParameters cpu;
  cpu.digit_bits = 11;
  EXPECT_EQ(expect_error([&] { validate(cpu, Primitive::RadixSort, Shape::Cpu, gpu); }),
            "tuning of radix-sort: digit_bits = 11 is outside 1 .. 10 (the CPU kernels' private tables grow as 2^digit_bits)");
  cpu.digit_bits = 8;
  cpu.chunks_per_compute_unit = 0;
  EXPECT_NE(expect_error([&] { validate(cpu, Primitive::Scan, Shape::Cpu, gpu); }).find("chunks_per_compute_unit = 0"), std::string::npos);
}

// Records for other devices were never looked at: a database with a kernel 'fft' or a negative
// chunk count for another vendor's CPU loaded, and `bench tune` wrote them back.
TEST(Tuning, EveryRecordIsCheckedWhateverItsDevice) {
  const auto check = [](const std::string& records) {
    return expect_error([&] { check_database(TuningDatabase::parse(R"({"records": [)" + records + "]}", "t.json")); });
  };
  const std::string good = R"({"kernel": "scan", "shape": "gpu", "device": {"vendor": "X"}, "parameters": {"group_size": 64}})";
  EXPECT_NO_THROW(check_database(TuningDatabase::parse(R"({"records": [)" + good + "]}", "t.json")));
  EXPECT_EQ(check(good + R"(, {"kernel": "fft", "shape": "cpu", "device": {"vendor": "Y"}, "parameters": {}})"),
            "t.json: records[1] (fft, cpu): unknown kernel (one of: scan, compact, radix-sort)");
  EXPECT_EQ(check(R"({"kernel": "compact", "shape": "cpu", "device": {"vendor": "Y"}, "parameters": {"chunks_per_compute_unit": -3}})"),
            "t.json: records[0] (compact, cpu): tuning of compact: chunks_per_compute_unit = -3 is outside 1 .. 256");
  EXPECT_EQ(check(R"({"kernel": "radix-sort", "shape": "gpu", "device": {"type": "gpu"}, "parameters": {"group_size": 100}})"),
            "t.json: records[0] (radix-sort, gpu): tuning of radix-sort: group_size = 100 must be a positive multiple of 16 (the group "
            "scan's rakes)");
  EXPECT_EQ(check(R"({"kernel": "scan", "shape": "gpu", "device": {"type": "gpu"}, "parameters": {"digit_bits": 4}})"),
            "t.json: records[0] (scan, gpu): scan (gpu shape) has no parameter 'digit_bits' (known: group_size, "
            "items_per_work_item)");
  // The device's own limits wait for the device: 4096 work-items suit some GPU.
  EXPECT_NO_THROW(check_database(TuningDatabase::parse(
      R"({"records": [{"kernel": "scan", "shape": "gpu", "device": {"type": "gpu"}, "parameters": {"group_size": 4096}}]})", "t.json")));
}

TEST(Tuning, ADriverRefusesParametersTheTestDeviceCannotRun) {
  LaunchParameters p;
  p.group_size = static_cast<std::int64_t>(runtime().info().max_work_group_size) + 16;
  const std::string message = expect_error([&] { Scanner scanner(runtime(), Shape::Gpu, p); });
  EXPECT_NE(message.find("work-items per group of '" + runtime().info().name + "'"), std::string::npos) << message;
}

// Non-default records on the test's device, both shapes, at sizes with partial chunks and blocks.
struct Tuned {
  const char* name;
  LaunchParameters cpu, gpu;
};

std::vector<Tuned> tuned_parameter_sets() {
  std::vector<Tuned> sets;
  LaunchParameters cpu, gpu;
  cpu.chunks_per_compute_unit = 1;
  cpu.min_chunk_items = 1000;
  cpu.digit_bits = 10;
  gpu.group_size = 64;
  gpu.items_per_work_item = 8;
  sets.push_back({"few_chunks_wide_digits_small_groups", cpu, gpu});
  cpu.chunks_per_compute_unit = 16;
  cpu.min_chunk_items = 64;
  cpu.digit_bits = 5;
  gpu.group_size = 128;
  gpu.items_per_work_item = 1;
  sets.push_back({"many_chunks_narrow_digits_one_item", cpu, gpu});
  return sets;
}

constexpr std::size_t kTunedSizes[] = {1, 999, 70001};

TEST(TunedKernels, EqualTheReferencesWithNonDefaultRecords) {
  for (const Tuned& tuned : tuned_parameter_sets()) {
    for (const Shape shape : {Shape::Cpu, Shape::Gpu}) {
      const LaunchParameters& p = shape == Shape::Cpu ? tuned.cpu : tuned.gpu;
      Scanner scanner(runtime(), shape, p);
      Compactor compactor(runtime(), shape, p);
      RadixSorter keys_sorter(runtime(), KeyType::U32, false, shape, p);
      RadixSorter pairs_sorter(runtime(), KeyType::U64, true, shape, p);
      EXPECT_EQ(scanner.parameters(), p);
      for (const std::size_t n : kTunedSizes) {
        SCOPED_TRACE(std::string(tuned.name) + " " + to_string(shape) + " n=" + std::to_string(n));
        const auto values = random_values<std::uint32_t>(n, 0xFFFF, 31 + n);
        std::vector<std::uint32_t> expected(n);
        reference::scan(values, expected, ScanKind::Inclusive);
        const cl::Buffer in = upload(runtime(), values, "scan input");
        const cl::Buffer out = runtime().buffer(CL_MEM_READ_WRITE, n * 4, "scan output");
        scanner.run(in, out, n, ScanKind::Inclusive);
        EXPECT_EQ(download<std::uint32_t>(runtime(), out, n), expected);

        auto sorted = random_values<std::uint32_t>(n, 0xFF, 41 + n);
        std::sort(sorted.begin(), sorted.end());
        const auto unique_expected = reference::unique(sorted);
        const cl::Buffer sorted_buffer = upload(runtime(), sorted, "unique input");
        const std::size_t kept = compactor.unique(sorted_buffer, out, n);
        EXPECT_EQ(download<std::uint32_t>(runtime(), out, kept), unique_expected);

        auto keys = random_values<std::uint32_t>(n, (1u << 20) - 1, 51 + n);
        auto expected_keys = keys;
        std::sort(expected_keys.begin(), expected_keys.end());
        const cl::Buffer keys_buffer = upload(runtime(), keys, "sort keys");
        keys_sorter.sort(keys_buffer, nullptr, n, 20);
        EXPECT_EQ(download<std::uint32_t>(runtime(), keys_buffer, n), expected_keys);

        auto wide = random_values<std::uint64_t>(n, ~std::uint64_t{0}, 61 + n);
        std::vector<std::uint32_t> indices(n);
        std::iota(indices.begin(), indices.end(), 0u);
        auto expected_wide = wide;
        auto expected_indices = indices;
        reference::radix_sort(expected_wide, &expected_indices, 64);
        const cl::Buffer wide_buffer = upload(runtime(), wide, "sort keys");
        const cl::Buffer index_buffer = upload(runtime(), indices, "sort values");
        pairs_sorter.sort(wide_buffer, &index_buffer, n, 64);
        EXPECT_EQ(download<std::uint64_t>(runtime(), wide_buffer, n), expected_wide);
        EXPECT_EQ(download<std::uint32_t>(runtime(), index_buffer, n), expected_indices);
      }
    }
  }
}

}  // namespace
}  // namespace splatcl::primitives::testing
