#pragma once
// A command's outputs as one unit: checked before any work, written to staged names beside their
// targets, and renamed onto them together at the end, so a failure anywhere (a late write, a
// render, a second output) leaves no output of that run behind.
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace splatcl {

// Fails before a long run, not after it: `path`, given as option `what` ("-o", "--stats"), must not
// be a directory, and its directory must exist and be writable (a probe file is written and
// removed, so a read-only or full file system is caught too, whoever runs it). Throws Error naming
// the option, the file and the cause. An empty path (the output not asked for) passes. Temporaries
// of `path` left by a killed earlier run are removed (io/atomic_file.hpp).
void check_output_file(const std::string& path, const std::string& what);

// The part of check_output_file that reads no folder listing and writes nothing: `path` is not a
// directory and its folder exists (through links). For callers that check many outputs of one
// folder (batch: each model's files), probing and clearing temporaries once per folder themselves.
// Also that its file name leaves room for the temporary names splatcl writes beside it
// (kTemporaryNameBytes and its extension more, within the file system's name limit). Returns the
// folder the file lies in (through links); empty for an empty path.
inline constexpr std::size_t kTemporaryNameBytes = 32;  // ".partial" + pid + ".tmp" + pid, pids of up to 10 digits
std::filesystem::path check_output_path(const std::string& path, const std::string& what);

// Throws Error "cannot write WHAT DIR: directory DIR is not writable (CAUSE)" unless a file can be
// created, written and removed in the existing directory `dir`.
void check_writable_directory(const std::string& dir, const std::string& what);

// The form two paths are compared in: absolute, with symbolic links and "." / ".." resolved as
// far as the path exists (a dangling link to the file it would make: two such links to one file
// are one output).
std::filesystem::path comparable_path(const std::string& path);
// Whether `inner` (a comparable_path) is `outer` or lies below it.
bool path_within(const std::filesystem::path& inner, const std::filesystem::path& outer);

// Throws Error when two of the given (option, path) outputs name the same file; empty paths are skipped.
void check_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs);

// Throws Error "OPTION OUT would overwrite the input IN" when an output names the same file as one
// of the (what, path) inputs (the model, a .csm an `ao` run reads); empty paths are skipped.
void check_outputs_spare_inputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                                const std::vector<std::pair<std::string, std::string>>& inputs);

// The extension of `path` in lower case (".ply", ".exr"; "" for none): what writers choose by.
std::string output_extension(const std::string& path);
// Throws Error "OPTION PATH: the file must end in EXT (what it holds)" unless `path` (if given) has
// one of `extensions` (lower case: ".ply"), compared by output_extension.
void check_output_extension(const std::string& path, const std::string& option, const std::vector<std::string>& extensions,
                            const std::string& holds);

class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  // Removes every staged file not yet committed.
  ~StagedOutputs();

  // The name to write `path`'s contents to: in the same directory (so the rename is atomic) with
  // the same extension (writers that pick the format from it still do). commit() renames the staged
  // files in the order stage() was called.
  std::string stage(const std::string& path);
  // Calls write(staged name) for a path given to stage(); an Error it throws is rethrown with the
  // staged name replaced by `path`, so messages name the file the user asked for.
  void write(const std::string& path, const std::function<void(const std::string& staged)>& write);
  // Renames every staged file onto its target. A staged file that was not written is an error; on
  // any failure the remaining staged files are removed and Error names the target.
  void commit();

 private:
  struct Entry {
    std::string target, through, staged;  // as given, written_through(target), the staged name
    int in_flight = -1;  // io/in_flight.hpp: removed by a terminating signal until committed
  };
  std::vector<Entry> entries_;
  std::size_t committed_ = 0;
};

}  // namespace splatcl
