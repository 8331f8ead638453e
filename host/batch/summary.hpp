#pragma once
// The summary of a batch run (one per shard) and the merge of shard summaries into one.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/runner.hpp"
#include "batch/shard.hpp"

namespace splatcl::batch {

struct RunInfo {
  std::string input;              // manifest or directory, as given
  std::string output_dir;
  std::string working_directory;  // absolute: what the relative paths above (and models' inputs) are relative to
  std::string manifest_checksum;  // of the whole model list, before sharding
  std::size_t manifest_models = 0;
  Shard shard;
  unsigned jobs = 1;
  std::string device;             // device name, or "reference"
  std::string started;            // ISO 8601 UTC
  double wall_s = 0;
};

// {"format": "splatcl-batch-summary", "version": 1, ..., "shard": {"count": N, "indices": [i]},
//  "counts": {...}, "models": [per-model result, in id order]}.
nlohmann::json make_summary(const RunInfo& info, const std::vector<ModelResult>& results);

// summary.json for a whole run, summary-I-of-N.json for shard I of N.
std::string summary_name(const Shard& shard);

// Merges summaries of shards of one run (same manifest checksum and shard count, no shard or
// model twice). Unless `partial`, every shard 0..N-1 must be present. Throws Error naming the
// offending file. `named` pairs a file name (for messages) with its parsed contents.
nlohmann::json merge_summaries(const std::vector<std::pair<std::string, nlohmann::json>>& named, bool partial);

// Reads and checks a summary file. Throws Error naming it.
nlohmann::json read_summary(const std::string& path);

// Models with status "failed" in a summary.
std::size_t failed_models(const nlohmann::json& summary);

// The current time as ISO 8601 UTC ("2026-11-22T01:55:00Z").
std::string utc_now();

}  // namespace splatcl::batch
