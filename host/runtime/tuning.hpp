#pragma once
// Per-device launch parameters, as CLBlast keeps them: one tuning record per kernel and shape, found
// by the device's vendor, name and type in a database (data/tuning.json, embedded in the binary;
// $SPLATCL_TUNING names another file). A record holds only the parameters it changes; the drivers
// start from their defaults, apply the record and validate the result against the device's limits
// before any launch. `splatcl bench tune` measures the records (host/bench/tune.hpp).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/runtime.hpp"

namespace splatcl {

// Environment variable naming a tuning database to use instead of the embedded data/tuning.json.
inline constexpr const char* kTuningEnvVar = "SPLATCL_TUNING";

struct TuningRecord {
  std::string kernel;  // "scan", "compact", "radix-sort"
  std::string shape;   // "cpu" or "gpu"
  // The devices the record is for; an empty field matches any device. The record that names the
  // most fields among those matching wins (name and vendor and type before vendor and type, ...).
  std::string vendor, device_name, device_type;
  std::map<std::string, std::int64_t> parameters;
  // What `bench tune` measured (default and tuned times, size, date); carried, not interpreted.
  nlohmann::ordered_json measured = nlohmann::ordered_json::object();

  bool matches(const DeviceInfo& device) const;
  int specificity() const;  // fields named
};

class TuningDatabase {
 public:
  TuningDatabase() = default;
  // Parses a database; `source` names it in errors ("data/tuning.json", a path).
  static TuningDatabase parse(const std::string& text, const std::string& source);
  static TuningDatabase read(const std::string& path);
  // The database the drivers use: $SPLATCL_TUNING when set, else the embedded data/tuning.json.
  // Read once per process; an unreadable or malformed file is an Error naming it.
  static std::shared_ptr<const TuningDatabase> active();

  // The most specific record of `kernel` in `shape` that matches `device`; nullptr when none does.
  const TuningRecord* find(const std::string& kernel, const std::string& shape, const DeviceInfo& device) const;
  // Adds `record`, replacing one of the same kernel, shape and device fields; returns the replaced one.
  std::optional<TuningRecord> put(TuningRecord record);

  const std::vector<TuningRecord>& records() const { return records_; }
  const std::string& source() const { return source_; }
  std::string to_json_text() const;
  // Written through a temporary file renamed when complete.
  void write(const std::string& path) const;

 private:
  std::vector<TuningRecord> records_;
  std::string source_ = "tuning database";
};

// The record's device fields for `device` (what `bench tune` writes): its vendor, name and type.
TuningRecord record_for_device(const std::string& kernel, const std::string& shape, const DeviceInfo& device);

}  // namespace splatcl
