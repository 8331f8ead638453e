#include "primitives/tuning.hpp"

#include <algorithm>
#include <mutex>

#include "runtime/error.hpp"

namespace splatcl::primitives {
namespace {

#include "../../kernels/primitives_layout.h"

// The GPU kernels' layout, one source with them: the group scan's rakes divide the group; the radix
// sort's digit tables have GPU_RADIX entries per block, its per-way counts SPLIT_FIELD_BITS bits.
constexpr std::int64_t kScanRakes = GROUP_SCAN_RAKES;
constexpr std::int64_t kGpuRadix = GPU_RADIX;
constexpr std::int64_t kMaxGpuSortBlock = (std::int64_t{1} << SPLIT_FIELD_BITS) - 1;
// The CPU radix scatter stages 16 keys and values per digit in private memory: 2^digit_bits x 192 B
// for 64-bit keys with values, 192 KiB at 10 bits.
constexpr std::int64_t kMaxCpuDigitBits = 10;
constexpr std::int64_t kMaxChunksPerUnit = 256;
constexpr std::int64_t kMaxItemsPerWorkItem = 32;

std::int64_t* field(LaunchParameters& p, const std::string& name) {
  if (name == "chunks_per_compute_unit") return &p.chunks_per_compute_unit;
  if (name == "min_chunk_items") return &p.min_chunk_items;
  if (name == "digit_bits") return &p.digit_bits;
  if (name == "group_size") return &p.group_size;
  if (name == "items_per_work_item") return &p.items_per_work_item;
  return nullptr;
}

// The group scan's local scratch, in elements.
std::size_t group_scan_scratch(std::int64_t group_size) {
  return static_cast<std::size_t>(GROUP_SCAN_SCRATCH_IN(group_size));
}

[[noreturn]] void refuse(Primitive primitive, const std::string& name, std::int64_t value, const std::string& limit) {
  throw Error(std::string("tuning of ") + tuning_name(primitive) + ": " + name + " = " + std::to_string(value) + " " + limit);
}

}  // namespace

const char* tuning_name(Primitive primitive) {
  switch (primitive) {
    case Primitive::Scan: return "scan";
    case Primitive::Compact: return "compact";
    default: return "radix-sort";
  }
}

std::optional<Primitive> parse_tuning_name(const std::string& name) {
  for (const Primitive primitive : kPrimitives)
    if (name == tuning_name(primitive)) return primitive;
  return std::nullopt;
}

std::vector<std::string> tunable_parameters(Primitive primitive, Shape shape) {
  if (shape == Shape::Gpu) return {"group_size", "items_per_work_item"};
  if (primitive == Primitive::RadixSort) return {"digit_bits", "chunks_per_compute_unit", "min_chunk_items"};
  return {"chunks_per_compute_unit", "min_chunk_items"};
}

std::int64_t parameter(const LaunchParameters& parameters, const std::string& name) {
  LaunchParameters copy = parameters;
  const std::int64_t* value = field(copy, name);
  if (!value) throw Error("unknown launch parameter '" + name + "'");
  return *value;
}

void set_parameter(LaunchParameters& parameters, const std::string& name, std::int64_t value) {
  std::int64_t* target = field(parameters, name);
  if (!target) throw Error("unknown launch parameter '" + name + "'");
  *target = value;
}

LaunchParameters apply_record(const TuningRecord& record, Primitive primitive, Shape shape, const std::string& source) {
  LaunchParameters parameters;
  const auto names = tunable_parameters(primitive, shape);
  for (const auto& [name, value] : record.parameters) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw Error(source + ": " + record.kernel + " (" + record.shape + " shape) has no parameter '" + name + "' (known: " + known + ")");
    }
    set_parameter(parameters, name, value);
  }
  return parameters;
}

LaunchParameters tuned_parameters(const Runtime& runtime, Primitive primitive, Shape shape) {
  const auto database = TuningDatabase::active();
  {
    // Once per database: a record for another device or kernel was never looked at before.
    static std::mutex mutex;
    static const TuningDatabase* checked = nullptr;
    std::lock_guard lock(mutex);
    if (checked != database.get()) {
      check_database(*database);
      checked = database.get();
    }
  }
  const TuningRecord* record = database->find(tuning_name(primitive), to_string(shape), runtime.info());
  return record ? apply_record(*record, primitive, shape, database->source()) : LaunchParameters{};
}

std::size_t gpu_local_bytes(const LaunchParameters& p, Primitive primitive, std::size_t key_bytes, bool with_values) {
  const auto block = static_cast<std::size_t>(p.group_size * p.items_per_work_item);
  const std::size_t scratch = group_scan_scratch(p.group_size);
  switch (primitive) {
    case Primitive::Scan: return (block + scratch) * 4;
    case Primitive::Compact: return scratch * 4;
    default:  // radix_block_sort_gpu: keys, values, digits, a ulong scan scratch, two digit tables
      return block * (key_bytes + (with_values ? 4 : 0) + 4) + scratch * 8 + 2 * kGpuRadix * 4;
  }
}

namespace {

// The kernels' own bounds, the same on every device.
void validate_own_bounds(const LaunchParameters& p, Primitive primitive, Shape shape) {
  if (shape == Shape::Cpu) {
    if (p.chunks_per_compute_unit < 1 || p.chunks_per_compute_unit > kMaxChunksPerUnit)
      refuse(primitive, "chunks_per_compute_unit", p.chunks_per_compute_unit, "is outside 1 .. " + std::to_string(kMaxChunksPerUnit));
    if (p.min_chunk_items < 1) refuse(primitive, "min_chunk_items", p.min_chunk_items, "must be at least 1");
    if (primitive == Primitive::RadixSort && (p.digit_bits < 1 || p.digit_bits > kMaxCpuDigitBits))
      refuse(primitive, "digit_bits", p.digit_bits,
             "is outside 1 .. " + std::to_string(kMaxCpuDigitBits) + " (the CPU kernels' private tables grow as 2^digit_bits)");
    return;
  }
  const std::int64_t group = p.group_size;
  if (group < kScanRakes || group % kScanRakes != 0)
    refuse(primitive, "group_size", group, "must be a positive multiple of " + std::to_string(kScanRakes) + " (the group scan's rakes)");
  if (p.items_per_work_item < 1 || p.items_per_work_item > kMaxItemsPerWorkItem)
    refuse(primitive, "items_per_work_item", p.items_per_work_item, "is outside 1 .. " + std::to_string(kMaxItemsPerWorkItem));
  if (primitive == Primitive::RadixSort && group * p.items_per_work_item > kMaxGpuSortBlock)
    refuse(primitive, "items_per_work_item", p.items_per_work_item,
           "makes blocks of " + std::to_string(group * p.items_per_work_item) + " keys (at most " + std::to_string(kMaxGpuSortBlock) +
               ": " + std::to_string(SPLIT_FIELD_BITS) + "-bit per-way counts)");
}

}  // namespace

void check_database(const TuningDatabase& database) {
  const auto& records = database.records();
  for (std::size_t i = 0; i < records.size(); ++i) {
    const TuningRecord& record = records[i];
    const std::string where = database.source() + ": records[" + std::to_string(i) + "] (" + record.kernel + ", " + record.shape + ")";
    const auto primitive = parse_tuning_name(record.kernel);
    if (!primitive) throw Error(where + ": unknown kernel (one of: " + kTuningNames + ")");
    const Shape shape = parse_shape(record.shape);
    const LaunchParameters parameters = apply_record(record, *primitive, shape, where);
    try {
      validate_own_bounds(parameters, *primitive, shape);
    } catch (const Error& e) {
      throw Error(where + ": " + e.what());
    }
  }
}

void validate(const LaunchParameters& p, Primitive primitive, Shape shape, const DeviceInfo& device, std::size_t key_bytes,
              bool with_values) {
  validate_own_bounds(p, primitive, shape);
  if (shape == Shape::Cpu) return;
  const std::int64_t group = p.group_size;
  if (static_cast<std::size_t>(group) > device.max_work_group_size)
    refuse(primitive, "group_size", group,
           "exceeds the " + std::to_string(device.max_work_group_size) + " work-items per group of '" + device.name + "'");
  const std::size_t local = gpu_local_bytes(p, primitive, key_bytes, with_values);
  if (local > device.local_mem_bytes)
    refuse(primitive, "group_size", group,
           "with items_per_work_item = " + std::to_string(p.items_per_work_item) + " needs " + std::to_string(local) +
               " B of local memory, more than the " + std::to_string(device.local_mem_bytes) + " B of '" + device.name + "'");
}

void validate_built_kernel(const cl::Kernel& kernel, const char* label, std::size_t group_size, const DeviceInfo& device) {
  std::size_t allowed = 0;
  cl_ulong local = 0;
  try {
    allowed = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device);
    local = kernel.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(device.device);
  } catch (...) {
    rethrow_as_error(std::string("querying the limits of kernel ") + label);
  }
  if (group_size > allowed)
    throw Error(std::string("kernel ") + label + " allows " + std::to_string(allowed) + " work-items per group on '" + device.name +
                "', the tuning asks for " + std::to_string(group_size));
  if (local > device.local_mem_bytes)
    throw Error(std::string("kernel ") + label + " needs " + std::to_string(local) + " B of local memory, more than the " +
                std::to_string(device.local_mem_bytes) + " B of '" + device.name + "'");
}

std::string describe(const LaunchParameters& parameters, Primitive primitive, Shape shape) {
  std::string text;
  for (const auto& name : tunable_parameters(primitive, shape))
    text += (text.empty() ? "" : " ") + name + "=" + std::to_string(parameter(parameters, name));
  return text;
}

}  // namespace splatcl::primitives
