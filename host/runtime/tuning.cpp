#include "runtime/tuning.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <mutex>

#include "io/atomic_file.hpp"
#include "io/json_keys.hpp"
#include "io/text_file.hpp"
#include "runtime/embedded.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kShippedName = "tuning.json";

std::string string_field(const Json& object, const char* key, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) return {};
  if (!it->is_string()) throw Error(where + ": '" + key + "' must be a string");
  return it->get<std::string>();
}

TuningRecord record_from_json(const nlohmann::json& plain, const std::string& where) {
  static constexpr std::initializer_list<const char*> known = {"kernel", "shape", "device", "parameters", "measured"};
  if (!plain.is_object()) throw Error(where + ": a record must be an object");
  if (const auto key = unknown_key(plain, known)) throw Error(where + ": unknown key '" + *key + "' (known: " + key_list(known) + ")");
  const Json json = plain;
  TuningRecord record;
  record.kernel = string_field(json, "kernel", where);
  record.shape = string_field(json, "shape", where);
  if (record.kernel.empty()) throw Error(where + ": 'kernel' is missing");
  if (record.shape != "cpu" && record.shape != "gpu") throw Error(where + ": 'shape' must be \"cpu\" or \"gpu\"");
  if (const auto device = json.find("device"); device != json.end()) {
    static constexpr std::initializer_list<const char*> device_keys = {"vendor", "name", "type"};
    if (!device->is_object()) throw Error(where + ": 'device' must be an object");
    if (const auto key = unknown_key(plain.at("device"), device_keys))
      throw Error(where + ": unknown device key '" + *key + "' (known: " + key_list(device_keys) + ")");
    record.vendor = string_field(*device, "vendor", where);
    record.device_name = string_field(*device, "name", where);
    record.device_type = string_field(*device, "type", where);
  }
  const auto parameters = json.find("parameters");
  if (parameters == json.end() || !parameters->is_object()) throw Error(where + ": 'parameters' must be an object");
  for (const auto& [name, value] : parameters->items()) {
    if (!value.is_number_integer()) throw Error(where + ": parameter '" + name + "' must be an integer");
    record.parameters[name] = value.get<std::int64_t>();
  }
  if (const auto measured = json.find("measured"); measured != json.end()) {
    // What bench tune writes there (informative only): closed like the record's other objects.
    static constexpr std::initializer_list<const char*> measured_keys = {"size", "size_unit", "default_ms", "tuned_ms", "gain", "candidates", "date"};
    if (!measured->is_object()) throw Error(where + ": 'measured' must be an object");
    if (const auto key = unknown_key(*measured, measured_keys))
      throw Error(where + ": unknown measured key '" + *key + "' (known: " + key_list(measured_keys) + ")");
    record.measured = *measured;
  }
  return record;
}

Json record_to_json(const TuningRecord& record) {
  Json device = Json::object();
  if (!record.vendor.empty()) device["vendor"] = record.vendor;
  if (!record.device_name.empty()) device["name"] = record.device_name;
  if (!record.device_type.empty()) device["type"] = record.device_type;
  Json parameters = Json::object();
  for (const auto& [name, value] : record.parameters) parameters[name] = value;
  Json json{{"kernel", record.kernel}, {"shape", record.shape}, {"device", device}, {"parameters", parameters}};
  if (!record.measured.empty()) json["measured"] = record.measured;
  return json;
}

bool same_target(const TuningRecord& a, const TuningRecord& b) {
  return a.kernel == b.kernel && a.shape == b.shape && a.vendor == b.vendor && a.device_name == b.device_name &&
         a.device_type == b.device_type;
}

}  // namespace

bool TuningRecord::matches(const DeviceInfo& device) const {
  return (vendor.empty() || vendor == device.vendor) && (device_name.empty() || device_name == device.name) &&
         (device_type.empty() || device_type == device.type);
}

int TuningRecord::specificity() const {
  return static_cast<int>(!vendor.empty()) + static_cast<int>(!device_name.empty()) + static_cast<int>(!device_type.empty());
}

TuningDatabase TuningDatabase::parse(const std::string& text, const std::string& source) {
  nlohmann::json json;
  try {
    json = parse_json_once_per_key<nlohmann::json>(text, source);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": not valid JSON: " + e.what());
  }
  if (!json.is_object() || !json.contains("records") || !json["records"].is_array())
    throw Error(source + ": not a tuning database (no \"records\" array)");
  if (const auto key = unknown_key(json, {"about", "records"}))
    throw Error(source + ": unknown key '" + *key + "' (known: about, records)");
  TuningDatabase database;
  database.source_ = source;
  const auto& records = json["records"];
  for (std::size_t i = 0; i < records.size(); ++i) {
    const std::string where = source + ": records[" + std::to_string(i) + "]";
    TuningRecord record = record_from_json(records[i], where);
    // put() replaces a record for the same target (bench tune's update); in a file, the later of
    // two such records won silently.
    for (std::size_t j = 0; j < database.records_.size(); ++j)
      if (same_target(database.records_[j], record))
        throw Error(fmt::format("{}: the same kernel, shape and devices as an earlier record", where));
    database.put(std::move(record));
  }
  return database;
}

TuningDatabase TuningDatabase::read(const std::string& path) { return parse(read_text_file(path, "tuning database"), path); }

std::shared_ptr<const TuningDatabase> TuningDatabase::active() {
  static std::mutex mutex;
  static std::shared_ptr<const TuningDatabase> database;
  std::lock_guard lock(mutex);
  if (!database) {
    const char* path = std::getenv(kTuningEnvVar);
    database = std::make_shared<const TuningDatabase>(
        path && *path ? read(path) : parse(std::string(embedded_data().at(kShippedName)), "data/tuning.json"));
  }
  return database;
}

const TuningRecord* TuningDatabase::find(const std::string& kernel, const std::string& shape, const DeviceInfo& device) const {
  const TuningRecord* best = nullptr;
  for (const auto& record : records_)
    if (record.kernel == kernel && record.shape == shape && record.matches(device) &&
        (!best || record.specificity() > best->specificity()))
      best = &record;
  return best;
}

std::optional<TuningRecord> TuningDatabase::put(TuningRecord record) {
  for (auto& existing : records_)
    if (same_target(existing, record)) {
      std::optional<TuningRecord> replaced = std::move(existing);
      existing = std::move(record);
      return replaced;
    }
  records_.push_back(std::move(record));
  return std::nullopt;
}

std::string TuningDatabase::to_json_text() const {
  Json records = Json::array();
  for (const auto& record : records_) records.push_back(record_to_json(record));
  const Json json{{"about",
                   "splatcl launch parameters per kernel, shape and device (docs/portability.md, 'Tuning'); written by "
                   "splatcl bench tune"},
                  {"records", records}};
  return json_text(json) + "\n";
}

void TuningDatabase::write(const std::string& path) const { write_file_atomically(path, to_json_text()); }

TuningRecord record_for_device(const std::string& kernel, const std::string& shape, const DeviceInfo& device) {
  TuningRecord record;
  record.kernel = kernel;
  record.shape = shape;
  record.vendor = device.vendor;
  record.device_name = device.name;
  record.device_type = device.type;
  return record;
}

}  // namespace splatcl
