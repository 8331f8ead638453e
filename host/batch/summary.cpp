#include "batch/summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "io/json_keys.hpp"
#include "io/text_file.hpp"
#include "runtime/error.hpp"

namespace splatcl::batch {
namespace {

constexpr const char* kFormat = "splatcl-batch-summary";
constexpr int kVersion = 1;

// ok = built + reused: a failed model counts as failed only (it was counted as built, whatever it did).
nlohmann::json counts(const nlohmann::json& models) {
  std::size_t ok = 0, failed = 0, reused = 0;
  for (const auto& m : models) {
    const bool model_ok = m.value("status", "") == "ok";
    if (model_ok) ++ok;
    else ++failed;
    if (model_ok && m.value("reused", false)) ++reused;  // a merged summary's failed model may say reused
  }
  return {{"models", models.size()}, {"ok", ok}, {"failed", failed}, {"reused", reused}, {"built", ok - reused}};
}

}  // namespace

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

nlohmann::json make_summary(const RunInfo& info, const std::vector<ModelResult>& results) {
  nlohmann::json models = nlohmann::json::array();
  std::vector<const ModelResult*> sorted;
  for (const auto& r : results) sorted.push_back(&r);
  std::sort(sorted.begin(), sorted.end(), [](const ModelResult* a, const ModelResult* b) { return a->id < b->id; });
  for (const ModelResult* r : sorted) models.push_back(to_json(*r));
  return {{"format", kFormat},
          {"version", kVersion},
          {"generator", "splatcl 0.1.0"},
          {"input", info.input},
          {"output_dir", info.output_dir},
          {"working_directory", info.working_directory},
          {"manifest_checksum", info.manifest_checksum},
          {"manifest_models", info.manifest_models},
          {"shard", {{"count", info.shard.count}, {"indices", {info.shard.index}}}},
          {"jobs", info.jobs},
          {"device", info.device},
          {"started", info.started},
          {"wall_s", info.wall_s},
          {"counts", counts(models)},
          {"models", models}};
}

std::string summary_name(const Shard& shard) {
  return shard.whole() ? "summary.json" : fmt::format("summary-{}-of-{}.json", shard.index, shard.count);
}

nlohmann::json read_summary(const std::string& path) {
  const std::string text = read_text_file(path, "summary");
  nlohmann::json doc;
  try {
    doc = parse_json_once_per_key<nlohmann::json>(text, path);
  } catch (const nlohmann::json::exception&) {
    throw Error(path + ": not valid JSON (not a complete splatcl batch summary)");
  }
  if (!doc.is_object() || doc.value("format", "") != kFormat) throw Error(path + ": not a splatcl batch summary");
  if (doc.value("version", 0) != kVersion) throw Error(fmt::format("{}: summary version {} (this splatcl reads {})", path, doc.value("version", 0), kVersion));
  // What make_summary and merge_summaries write; merge copied any other key of the first summary.
  JsonFields{path + ": "}.known_keys(doc, "the summary",
                                     {"format", "version", "generator", "input", "output_dir", "working_directory", "manifest_checksum", "manifest_models", "shard",
                                      "jobs", "device", "started", "wall_s", "counts", "models", "merged_from"});
  // Each model's entry as to_json (runner.cpp) writes it: merge copies the entries as they are.
  if (const auto models = doc.find("models"); models != doc.end() && models->is_array())
    for (std::size_t i = 0; i < models->size(); ++i) {
      const nlohmann::json& m = (*models)[i];
      const std::string at = fmt::format("models[{}]", i);
      JsonFields{path + ": "}.known_keys(m, at, {"id", "input", "status", "reused", "input_checksum", "input_bytes", "outputs", "total_ms", "reason", "warning"});
      if (const auto outputs = m.find("outputs"); outputs != m.end() && outputs->is_object())
        for (const auto& [kind, output] : outputs->items())
          JsonFields{path + ": "}.known_keys(output, at + ".outputs." + kind, {"reused", "params", "params_checksum", "files", "build_ms"});
    }
  try {
    (void)doc.at("manifest_checksum").get<std::string>();
    (void)doc.at("manifest_models").get<std::size_t>();
    (void)doc.at("shard").at("count").get<unsigned>();
    for (const auto& i : doc.at("shard").at("indices")) (void)i.get<unsigned>();
    for (const auto& m : doc.at("models")) (void)m.at("id").get<std::string>();
  } catch (const nlohmann::json::exception&) {
    throw Error(path + ": incomplete summary (missing manifest_checksum, shard or models)");
  }
  // The paths merge checks its -o against: strings, the working directory absolute.
  for (const char* key : {"input", "output_dir", "working_directory"})
    if (doc.contains(key) && !doc[key].is_string()) throw Error(fmt::format("{}: '{}' is not a string", path, key));
  if (const std::string wd = doc.value("working_directory", ""); !wd.empty() && !std::filesystem::path(wd).is_absolute())
    throw Error(path + ": 'working_directory' is not an absolute path");
  return doc;
}

nlohmann::json merge_summaries(const std::vector<std::pair<std::string, nlohmann::json>>& named, bool partial) {
  if (named.empty()) throw Error("batch merge: no summaries given");
  const auto& [first_name, first] = named.front();
  const std::string checksum = first.at("manifest_checksum"), device = first.value("device", "");
  const unsigned count = first.at("shard").at("count");
  std::map<unsigned, std::string> shards;
  std::map<std::string, std::string> model_file;
  nlohmann::json models = nlohmann::json::array();
  std::string started;
  double wall = 0;
  nlohmann::json sources = nlohmann::json::array();
  for (const auto& [name, s] : named) {
    if (s.at("manifest_checksum") != checksum)
      throw Error(fmt::format("{}: from a different run than {}: other models, inputs or parameters (manifest checksum {} vs {})", name,
                              first_name, s.at("manifest_checksum").get<std::string>(), checksum));
    // Same parameters, but another device (or the native reference) could round differently.
    if (s.value("device", "") != device)
      throw Error(fmt::format("{}: ran on device '{}', {} on '{}'; rerun the shards on one device", name, s.value("device", ""), first_name, device));
    if (s.at("shard").at("count") != count)
      throw Error(fmt::format("{}: split into {} shards, {} into {}", name, s.at("shard").at("count").get<unsigned>(), first_name, count));
    for (const auto& index : s.at("shard").at("indices")) {
      const unsigned i = index;
      if (const auto [at, fresh] = shards.emplace(i, name); !fresh)
        throw Error(fmt::format("{}: shard {}/{} is also in {}", name, i, count, at->second));
    }
    for (const auto& m : s.at("models")) {
      const std::string id = m.at("id");
      if (const auto [at, fresh] = model_file.emplace(id, name); !fresh)
        throw Error(fmt::format("{}: model '{}' is also in {}", name, id, at->second));
      models.push_back(m);
    }
    const std::string s_started = s.value("started", "");
    if (started.empty() || (!s_started.empty() && s_started < started)) started = s_started;
    wall = std::max(wall, s.value("wall_s", 0.0));
    sources.push_back(name);
  }
  std::string missing;
  for (unsigned i = 0; i < count; ++i)
    if (!shards.count(i)) missing += (missing.empty() ? "" : ", ") + fmt::format("{}/{}", i, count);
  if (!missing.empty() && !partial) throw Error(fmt::format("batch merge: missing shard {} (pass --partial to merge anyway)", missing));
  const std::size_t expected = first.at("manifest_models");
  if (missing.empty() && models.size() != expected)
    throw Error(fmt::format("batch merge: the shards hold {} models, the manifest {}", models.size(), expected));
  std::sort(models.begin(), models.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.at("id").get<std::string>() < b.at("id").get<std::string>();
  });
  nlohmann::json indices = nlohmann::json::array();
  for (const auto& [i, name] : shards) indices.push_back(i);
  nlohmann::json merged = first;
  // The runs' paths are relative to their working directory: kept only when every shard ran in one.
  for (const auto& [name, s] : named)
    if (s.value("working_directory", "") != first.value("working_directory", "")) merged.erase("working_directory");
  merged["shard"] = {{"count", count}, {"indices", indices}};
  merged["started"] = started;
  merged["wall_s"] = wall;
  merged["merged_from"] = sources;
  merged["counts"] = counts(models);
  merged["models"] = models;
  merged.erase("jobs");
  return merged;
}

std::size_t failed_models(const nlohmann::json& summary) {
  std::size_t failed = 0;
  for (const auto& m : summary.at("models"))
    if (m.value("status", "") != "ok") ++failed;
  return failed;
}

}  // namespace splatcl::batch
