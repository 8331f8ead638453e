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
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/manifest.hpp"

namespace splatcl {
class KeyLocks;
}

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
  std::string made_by;            // the OpenCL device's name, or "reference"
  std::vector<OutputFile> files;  // the data file, then its statistics
  double build_ms = 0;            // 0 when reused
};

struct ModelResult {
  std::string id, input;
  bool ok = false;
  std::string reason;  // why it failed
  std::string warning;  // what loading the mesh found wrong (core/mesh.hpp: MeshProblems); empty when clean
  std::string input_checksum;
  std::uint64_t input_bytes = 0;
  std::vector<OutputResult> outputs;  // complete outputs only (a failed model may have some)
  // The record's entries (by kind) of outputs this run was not asked for (--outputs), kept in the
  // record as they were when it is of the same input bytes: a later run that wants them reuses them.
  nlohmann::json carried_outputs = nlohmann::json::object();
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

// Refuses, before any work, a run whose outputs would overwrite what it reads or each other. Throws
// Error naming the paths when: the output directory is, lies inside or contains the input directory
// (`input_is_directory`), or contains the manifest among a model's outputs; the summary is the
// manifest, a model's input or one of any model's outputs; a model's output is another model's input.
void check_run_paths(const std::string& input, bool input_is_directory, const std::string& output_dir, const std::string& summary,
                     const std::vector<ModelEntry>& all_models);

// Creates the output directory when missing and checks that files can be written in it, so a run
// into a read-only or full directory fails before it computes anything. Throws Error naming it.
void prepare_output_directory(const std::string& output_dir);

// Two runs must not build the same model in one output directory at once: they would replace each
// other's files and records. A run holds the lock of each of its models (in OUTDIR/.splatcl-batch.lock)
// until its summary is written; a second run over any of them is refused with one line naming the
// model and the other run's pid. Shards of one run hold disjoint models and run side by side. The
// summary file is locked too (a shard with no models, two runs naming one --summary), in the lock
// file of the summary's folder: two runs into different output directories naming one --summary
// both wrote it. Taken before the run removes any temporary: two copies of one shard (a requeued
// Slurm task while the first still runs on another node, whose pids this node cannot see) never
// delete each other's files.
struct RunLocks {
  std::unique_ptr<KeyLocks> models;
  std::unique_ptr<KeyLocks> summary;  // null when the summary's folder is the output directory
};
// Makes the output directory (prepare_output_directory) after a summary elsewhere is locked.
RunLocks lock_models(const std::vector<ModelEntry>& models, const std::string& output_dir, const std::string& summary_path);

// The per-model locks' file in the output directory.
inline constexpr const char* kLockFileName = ".splatcl-batch.lock";

// Output file names of a model, relative to the output directory.
std::string record_name(const std::string& id);  // ID.batch.json
std::string splats_name(const std::string& id);  // ID.splats.ply (+ ID.splats.json)
std::string csm_name(const std::string& id);     // ID.csm (+ ID.csm.json)
std::vector<std::string> output_names(const std::string& id);  // all of them, the record first

// Test hook: when the environment variable SPLATCL_BATCH_KILL_AFTER_WRITES=N is set, the process
// kills itself with SIGKILL right after its N-th completed file write, to test resumption.
inline constexpr const char* kKillAfterWritesVariable = "SPLATCL_BATCH_KILL_AFTER_WRITES";
// Test hook: SPLATCL_BATCH_HOLD_LOCKS_MS=N makes lock_models wait N ms after taking the locks, so a
// test can start a second run while the first one holds them.
inline constexpr const char* kHoldLocksVariable = "SPLATCL_BATCH_HOLD_LOCKS_MS";

}  // namespace splatcl::batch
