#pragma once
// Running a batch: for each model, the splat set (PLY + statistics JSON) and the coherent shadow
// map (.csm + statistics JSON) under the output directory, then a record OUTDIR/ID.batch.json
// listing the input's checksum, each output's parameters and parameters checksum, and each file's
// size and checksum. The record is written last, and every file atomically, so a run killed at
// any moment leaves only complete files; the next run reuses an output whose record matches the
// current input and parameters and whose files still have their recorded checksums, and rebuilds
// everything else. A model that fails (unreadable, empty, non-finite or degenerate mesh, a failed
// build) is recorded with its reason and the others go on.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/manifest.hpp"

namespace splatcl::batch {

struct RunOptions {
  std::string output_dir;
  std::string device;      // OpenCL device selector, as --device
  unsigned jobs = 1;       // models processed at once, each with its own OpenCL context
  bool force = false;      // rebuild even when a matching output exists
  bool reference = false;  // native C++ references instead of OpenCL
};

struct OutputFile {
  std::string path;  // relative to the output directory
  std::uint64_t bytes = 0;
  std::string checksum;
};

struct OutputResult {
  std::string kind;  // "splats" or "csm"
  bool reused = false;
  nlohmann::json params;
  std::string params_checksum;
  std::vector<OutputFile> files;  // the data file, then its statistics
  double build_ms = 0;            // 0 when reused
};

struct ModelResult {
  std::string id, input;
  bool ok = false;
  std::string reason;  // why it failed
  std::string input_checksum;
  std::uint64_t input_bytes = 0;
  std::vector<OutputResult> outputs;  // complete outputs only (a failed model may have some)
  double total_ms = 0;
  bool reused() const;  // every output reused: nothing was built
};

nlohmann::json to_json(const ModelResult& result);

// (models finished, models total, models failed so far, what is running now)
using BatchProgress = std::function<void(std::size_t, std::size_t, std::size_t, const std::string&)>;

// Processes `models` (results in the same order). Throws Error only for problems that would fail
// every model alike (no OpenCL device, output directory not writable); per-model problems are in
// the results.
// `finished` is called once per model as it completes (from the worker, serialised).
using ModelFinished = std::function<void(const ModelResult&)>;
std::vector<ModelResult> run_batch(const std::vector<ModelEntry>& models, const RunOptions& options, const BatchProgress& progress = {},
                                   const ModelFinished& finished = {});

// Output file names of a model, relative to the output directory.
std::string record_name(const std::string& id);  // ID.batch.json
std::string splats_name(const std::string& id);  // ID.splats.ply (+ ID.splats.json)
std::string csm_name(const std::string& id);     // ID.csm (+ ID.csm.json)

// Test hook: when the environment variable SPLATCL_BATCH_KILL_AFTER_WRITES=N is set, the process
// kills itself with SIGKILL right after its N-th completed file write, to test resumption.
inline constexpr const char* kKillAfterWritesVariable = "SPLATCL_BATCH_KILL_AFTER_WRITES";

}  // namespace splatcl::batch
