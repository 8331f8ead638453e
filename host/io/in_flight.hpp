#pragma once
// Files a process has half written (write_atomically's temporaries, StagedOutputs' staged names),
// and folders it made for its outputs, so that a signal that ends it — SIGTERM from scancel, a time
// limit or preemption, SIGINT, SIGHUP — removes them (the folders when empty) before it dies. A
// SIGKILL cannot be caught: the next run removes what it leaves
// (remove_dead_temporaries, batch's own clean-up).
#include <string>

namespace splatcl {

// Registers `path` while it is being written; returns a slot for unregister_in_flight (-1 when all
// slots are taken: the file is then left to the next run's clean-up).
int register_in_flight(const std::string& path);
// A folder the process made for its outputs: removed on such a signal when it is empty by then
// (after the files), as a failing run removes it.
int register_in_flight_folder(const std::string& path);
void unregister_in_flight(int slot);

// Installs handlers of SIGTERM, SIGINT and SIGHUP that unlink every registered file, remove every
// registered folder that is empty then, and end the process by the same signal (a shell or Slurm
// sees 128 + 15 = 143 for SIGTERM), as if there were no handler. Called once by main.
void remove_in_flight_files_on_termination();

// Test hook: SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS=N makes write_atomically wait N ms between writing
// a temporary and renaming it, so a test can signal a process while it has one.
inline constexpr const char* kPauseBeforeRenameVariable = "SPLATCL_TEST_PAUSE_BEFORE_RENAME_MS";

}  // namespace splatcl
