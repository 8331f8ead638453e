#pragma once
// The record format shared by every `splatcl bench` command:
//   {"machine": {...}, "records": [{"suite", "case", "impl", "device", "size", "size_unit", "runs",
//    "median_ms", "min_ms", "max_ms", "throughput", "throughput_unit", "peak_rss_mb", ...extra}]}
// Fields that do not apply to a record are left out of its JSON object. Docs tables are rendered
// from these files (bench/report.hpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/runtime.hpp"

namespace splatcl::bench {

// Insertion-ordered, so files read in the order of the format above.
using Json = nlohmann::ordered_json;

// Implementation names with a fixed meaning; peers use their library's name.
inline constexpr const char* kImplOpenCL = "opencl";
inline constexpr const char* kImplReference = "reference";
// Device name of records measured on the host CPU outside OpenCL.
inline constexpr const char* kHostDevice = "host";

struct Record {
  std::string suite;      // "primitives", "cluster"
  std::string case_name;  // "case" in JSON: "radix-sort-u32", "compact-unique"
  std::string impl;       // kImplOpenCL, kImplReference or a peer's name
  std::string device;     // OpenCL device name, or kHostDevice
  std::optional<std::uint64_t> size;
  std::string size_unit;  // "keys", "elements", "bytes"; empty when size is absent
  int runs = 0;
  double median_ms = 0;
  double min_ms = 0;
  double max_ms = 0;
  std::optional<double> throughput;  // size per second, in base units (keys/s, bytes/s)
  std::string throughput_unit;
  std::optional<double> peak_rss_mb;  // MiB (2^20 bytes), peak of the process while this case ran
  // Further fields ("bits", "lights", "shape", "variant", "device_ms", ...), written after the fixed ones.
  Json extra = Json::object();
};

// Extra fields that describe how a row was measured ("shape", "variant", "threads", "pocl_threads"
// of a thread-scaling run, "bytes" moved and "flops" done per run, "device_ms", "device_total_ms") rather than what:
// rows of one case that differ only in these, in impl and in device are compared with each other.
// Every other scalar extra field ("bits", "lights") names a variant of the problem itself.
bool describes_implementation(const std::string& extra_field);

struct Results {
  Json machine = Json::object();
  std::vector<Record> records;
};

Json to_json(const Record& record);
// Throws Error naming the missing or mistyped field.
Record record_from_json(const Json& json);

Json to_json(const Results& results);
Results results_from_json(const Json& json);

// Writes the results to `path` through a temporary file renamed when complete.
void write_results(const std::string& path, const Results& results);
// Throws Error naming the file when it cannot be read or is not a results file.
Results read_results(const std::string& path);
// The same for a file's text already in memory; `name` appears in errors.
Results parse_results(const std::string& text, const std::string& name);

// The process's command line (/proc/self/cmdline): its words, the program first, and as one line
// with each word quoted where a shell would need it (the machine block's `command`).
std::vector<std::string> command_words();
std::string command_line();

// What a reader needs to compare figures across machines: host, CPU, memory, OS, compiler and build,
// the OpenCL device (when given), the PoCL thread count, the date, the command and the load average.
Json machine_info(const DeviceInfo* device);

}  // namespace splatcl::bench
