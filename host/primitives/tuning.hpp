#pragma once
// Launch parameters of the primitives (scan, compaction, radix sort) per shape: the defaults, the
// tuning record of the device applied over them (runtime/tuning.hpp), and the checks that make any
// valid record safe to launch: results equal the references whatever the values.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/runtime.hpp"
#include "runtime/tuning.hpp"

namespace splatcl::primitives {

enum class Primitive { Scan, Compact, RadixSort };
inline constexpr Primitive kPrimitives[] = {Primitive::Scan, Primitive::Compact, Primitive::RadixSort};
// The kernel name of its tuning records: "scan", "compact", "radix-sort".
const char* tuning_name(Primitive primitive);
// The primitive of a record's kernel name; none for any other.
std::optional<Primitive> parse_tuning_name(const std::string& name);
inline constexpr const char* kTuningNames = "scan, compact, radix-sort";

struct LaunchParameters {
  // CPU shape: one work-item per chunk; chunks = min(n / min_chunk_items, compute units x
  // chunks_per_compute_unit), at least 1.
  std::int64_t chunks_per_compute_unit = 4;
  std::int64_t min_chunk_items = std::int64_t{1} << 15;
  std::int64_t digit_bits = 8;  // radix sort, CPU shape: key bits sorted per pass (the last pass takes the rest)
  // GPU shape: work-items per group, and consecutive elements per work-item in a block (scan:
  // values per item; compaction: rounds of one element per item; radix sort: keys per item).
  std::int64_t group_size = 256;
  std::int64_t items_per_work_item = 4;

  bool operator==(const LaunchParameters&) const = default;
};

// The parameter names a record of `primitive` in `shape` may set, in the order `bench tune` searches them.
std::vector<std::string> tunable_parameters(Primitive primitive, Shape shape);
std::int64_t parameter(const LaunchParameters& parameters, const std::string& name);
void set_parameter(LaunchParameters& parameters, const std::string& name, std::int64_t value);

// The defaults with `record`'s parameters applied. Throws Error naming the record's source for a
// parameter that does not apply to the primitive and shape.
LaunchParameters apply_record(const TuningRecord& record, Primitive primitive, Shape shape, const std::string& source);
// The parameters for the runtime's device: the most specific matching record of the active database
// (TuningDatabase::active()) over the defaults, or the defaults when none matches.
LaunchParameters tuned_parameters(const Runtime& runtime, Primitive primitive, Shape shape);

// Local memory one work-group of the GPU shape uses (the largest of the primitive's kernels), in bytes.
std::size_t gpu_local_bytes(const LaunchParameters& parameters, Primitive primitive, std::size_t key_bytes, bool with_values);
// Throws Error naming the primitive, the parameter, its value and the limit it breaks: the kernels'
// own bounds (group size a multiple of 16, block sizes, private arrays) and the device's
// (CL_DEVICE_MAX_WORK_GROUP_SIZE, CL_DEVICE_LOCAL_MEM_SIZE). key_bytes and with_values: radix sort.
void validate(const LaunchParameters& parameters, Primitive primitive, Shape shape, const DeviceInfo& device,
              std::size_t key_bytes = 4, bool with_values = false);
// Every record of `database`, whatever its device: a known kernel, parameters of its shape, and
// within the kernels' own bounds (the device's limits are checked when a device uses a record).
// Throws Error naming the database, the record's index and the cause. tuned_parameters checks the
// active database once; `bench tune` checks the one it merges into.
void check_database(const TuningDatabase& database);
// After the build: throws Error when the compiled kernel allows fewer work-items per group than
// `group_size` (CL_KERNEL_WORK_GROUP_SIZE) or needs more local memory than the device has.
void validate_built_kernel(const cl::Kernel& kernel, const char* label, std::size_t group_size, const DeviceInfo& device);

// "group_size=128 items_per_work_item=8": the parameters of a shape, for messages and tables.
std::string describe(const LaunchParameters& parameters, Primitive primitive, Shape shape);

}  // namespace splatcl::primitives
