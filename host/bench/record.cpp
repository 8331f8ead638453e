#include "bench/record.hpp"
#include "io/json_keys.hpp"

#include <sys/utsname.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <limits>
#include <thread>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/memory.hpp"
#include "io/text_file.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

// Keys written by to_json(Record) itself; everything else in a record object is an extra field.
const char* const kFixedFields[] = {"suite", "case", "impl", "device", "size", "size_unit", "runs", "median_ms",
                                    "min_ms", "max_ms", "throughput", "throughput_unit", "peak_rss_mb"};

bool is_fixed_field(const std::string& key) {
  for (const char* field : kFixedFields)
    if (key == field) return true;
  return false;
}

const Json& required(const Json& json, const char* key) {
  const auto it = json.find(key);
  if (it == json.end()) throw Error(std::string("benchmark record lacks '") + key + "'");
  return *it;
}

std::string required_string(const Json& json, const char* key) {
  const Json& value = required(json, key);
  if (!value.is_string()) throw Error(std::string("benchmark record field '") + key + "' is not a string");
  return value.get<std::string>();
}

double required_number(const Json& json, const char* key) {
  const Json& value = required(json, key);
  if (!value.is_number()) throw Error(std::string("benchmark record field '") + key + "' is not a number");
  return value.get<double>();
}

std::string optional_string(const Json& json, const char* key) {
  const auto it = json.find(key);
  if (it == json.end()) return {};
  if (!it->is_string()) throw Error(std::string("benchmark record field '") + key + "' is not a string");
  return it->get<std::string>();
}

std::optional<double> optional_number(const Json& json, const char* key) {
  const auto it = json.find(key);
  if (it == json.end()) return std::nullopt;
  if (!it->is_number()) throw Error(std::string("benchmark record field '") + key + "' is not a number");
  return it->get<double>();
}

std::string os_description() {
  std::string name;
  std::ifstream release("/etc/os-release");
  std::string line;
  while (std::getline(release, line)) {
    if (line.rfind("PRETTY_NAME=", 0) != 0) continue;
    name = line.substr(12);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
  }
  utsname uts{};
  if (::uname(&uts) == 0) {
    const std::string kernel = std::string(uts.sysname) + " " + uts.release + " " + uts.machine;
    name = name.empty() ? kernel : name + ", " + kernel;
  }
  return name;
}

std::string compiler_description() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("gcc ") + __VERSION__;
#else
  return "unknown compiler";
#endif
}

// CMake's build type, passed in by the build, plus what the compiler actually did.
std::string build_description() {
#ifdef SPLATCL_BUILD_TYPE
  std::string build = SPLATCL_BUILD_TYPE;
#else
  std::string build = "unknown build type";
#endif
#if defined(__OPTIMIZE__)
  build += ", optimized";
#endif
#if defined(NDEBUG)
  build += ", assertions off";
#endif
#if defined(__SANITIZE_ADDRESS__)
  build += ", AddressSanitizer";
#endif
  return build;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string hostname() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

// The 1-, 5- and 15-minute load averages: how busy the shared machine was when the results were taken.
Json load_average() {
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  if (!(in >> one >> five >> fifteen)) return nullptr;
  return Json::array({one, five, fifteen});
}

}  // namespace

bool describes_implementation(const std::string& extra_field) {
  static const char* const fields[] = {"shape", "variant", "threads", "pocl_threads", "bytes", "flops", "device_ms", "device_total_ms"};
  for (const char* field : fields)
    if (extra_field == field) return true;
  return false;
}

Json to_json(const Record& record) {
  Json json = Json::object();
  json["suite"] = record.suite;
  json["case"] = record.case_name;
  json["impl"] = record.impl;
  json["device"] = record.device;
  if (record.size) json["size"] = *record.size;
  if (record.size && !record.size_unit.empty()) json["size_unit"] = record.size_unit;
  json["runs"] = record.runs;
  json["median_ms"] = record.median_ms;
  json["min_ms"] = record.min_ms;
  json["max_ms"] = record.max_ms;
  if (record.throughput) json["throughput"] = *record.throughput;
  if (record.throughput && !record.throughput_unit.empty()) json["throughput_unit"] = record.throughput_unit;
  if (record.peak_rss_mb) json["peak_rss_mb"] = *record.peak_rss_mb;
  for (const auto& [key, value] : record.extra.items()) {
    if (is_fixed_field(key)) throw Error("benchmark record extra field '" + key + "' shadows a fixed field");
    json[key] = value;
  }
  return json;
}

Record record_from_json(const Json& json) {
  if (!json.is_object()) throw Error("benchmark record is not a JSON object");
  Record record;
  record.suite = required_string(json, "suite");
  record.case_name = required_string(json, "case");
  record.impl = required_string(json, "impl");
  record.device = required_string(json, "device");
  if (const auto it = json.find("size"); it != json.end()) {
    if (!it->is_number_unsigned()) throw Error("benchmark record field 'size' is not a non-negative integer");
    record.size = it->get<std::uint64_t>();
  }
  record.size_unit = optional_string(json, "size_unit");
  const double runs = required_number(json, "runs");
  if (runs < 1 || runs != std::floor(runs) || runs > std::numeric_limits<int>::max())
    throw Error("benchmark record field 'runs' is not a positive integer (at most 2^31 - 1)");
  record.runs = static_cast<int>(runs);
  record.median_ms = required_number(json, "median_ms");
  record.min_ms = required_number(json, "min_ms");
  record.max_ms = required_number(json, "max_ms");
  // A time no run can take: report printed it and compare read a change of +0.0 % against it.
  if (!(record.min_ms > 0 && record.min_ms <= record.median_ms && record.median_ms <= record.max_ms && std::isfinite(record.max_ms)))
    throw Error(fmt::format("benchmark record times must be finite with 0 < min_ms <= median_ms <= max_ms, got {} / {} / {}", record.min_ms,
                            record.median_ms, record.max_ms));
  record.throughput = optional_number(json, "throughput");
  record.throughput_unit = optional_string(json, "throughput_unit");
  record.peak_rss_mb = optional_number(json, "peak_rss_mb");
  for (const auto& [key, value] : json.items())
    if (!is_fixed_field(key)) record.extra[key] = value;
  return record;
}

Json to_json(const Results& results) {
  Json records = Json::array();
  for (const auto& record : results.records) records.push_back(to_json(record));
  return Json{{"machine", results.machine}, {"records", std::move(records)}};
}

Results results_from_json(const Json& json) {
  if (!json.is_object() || !json.contains("records") || !json["records"].is_array())
    throw Error("not a benchmark results file: expected {\"machine\": {...}, \"records\": [...]}");
  // A record keeps the fields it does not know (record.extra: suites add their own); the file's top
  // level has only these two.
  for (const auto& [key, value] : json.items())
    if (key != "machine" && key != "records")
      throw Error(fmt::format("unknown top-level key '{}' (known: machine, records)", printable(key)));
  Results results;
  if (const auto it = json.find("machine"); it != json.end() && it->is_object()) results.machine = *it;
  std::size_t index = 0;
  for (const auto& record : json["records"]) {
    try {
      results.records.push_back(record_from_json(record));
    } catch (const Error& e) {
      throw Error("record " + std::to_string(index) + ": " + e.what());
    }
    ++index;
  }
  return results;
}

void write_results(const std::string& path, const Results& results) {
  write_file_atomically(path, json_text(to_json(results)) + "\n");
}

Results read_results(const std::string& path) { return parse_results(read_text_file(path, ""), path); }

Results parse_results(const std::string& text, const std::string& path) {
  Json json;
  try {
    json = parse_json_once_per_key<Json>(text, path);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + " is not valid JSON: " + e.what());
  }
  try {
    return results_from_json(json);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
}

std::vector<std::string> command_words() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::vector<std::string> words;
  std::string word;
  while (std::getline(in, word, '\0')) words.push_back(word);
  return words;
}

std::string command_line() {
  std::string line;
  for (const std::string& word : command_words()) {
    const bool plain = !word.empty() && word.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos;
    std::string quoted = plain ? word : "'";
    if (!plain) {
      for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      quoted += "'";
    }
    line += (line.empty() ? "" : " ") + quoted;
  }
  return line;
}

Json machine_info(const DeviceInfo* device) {
  Json machine = Json::object();
  machine["hostname"] = hostname();
  const std::string cpu = proc_field("/proc/cpuinfo", "model name");
  machine["cpu_model"] = cpu.empty() ? "unknown" : cpu;
  machine["logical_cores"] = std::thread::hardware_concurrency();
  if (const std::string total = proc_field("/proc/meminfo", "MemTotal"); !total.empty()) {
    const double kib = std::strtod(total.c_str(), nullptr);
    machine["memory_gib"] = std::round(kib / (1024.0 * 1024.0) * 10.0) / 10.0;
  }
  machine["os"] = os_description();
  machine["compiler"] = compiler_description();
  machine["build"] = build_description();
  if (device) {
    machine["opencl_platform"] = device->platform;
    machine["opencl_device"] = device->name;
    machine["opencl_device_type"] = device->type;
    machine["opencl_device_version"] = device->version;
    try {
      std::string driver = device->device.getInfo<CL_DRIVER_VERSION>();
      while (!driver.empty() && (driver.back() == '\0' || driver.back() == ' ')) driver.pop_back();
      machine["opencl_driver_version"] = driver;
    } catch (const cl::Error&) {
      // The driver version is informative only; a device that refuses the query still benchmarks.
    }
    machine["opencl_compute_units"] = device->compute_units;
  }
  if (const char* threads = std::getenv("POCL_MAX_PTHREAD_COUNT")) machine["pocl_max_pthread_count"] = threads;
  machine["date"] = utc_now();
  machine["command"] = command_line();
  machine["load_average"] = load_average();
  return machine;
}

}  // namespace splatcl::bench
