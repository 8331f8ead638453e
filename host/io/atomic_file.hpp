#pragma once
// Outputs are written to a temporary name beside the target and renamed when complete, so a
// reader never sees a half-written file.
#include <functional>
#include <string>
#include <string_view>

namespace splatcl {

// The file that writing `path` replaces: `path` itself, or, when it is a symbolic link, the file it
// leads to through every link (a missing target of a dangling link included). Outputs are written
// through links: renaming onto the link itself replaced it with a plain file. Throws Error naming
// `path` for a loop of links.
std::string written_through(const std::string& path);

// Calls write(temp_path) and renames temp_path to path (to written_through(path), beside which the
// temporary lies). On any failure the temporary is removed
// and splatcl::Error names `path`.
void write_atomically(const std::string& path, const std::function<void(const std::string& temp_path)>& write);

// Removes the temporaries of `path` that a killed run left behind: PATH.tmpPID (write_atomically)
// and PATH.partialPID.EXT (io/output_files.hpp) whose process PID no longer exists on this machine.
// A live process's temporaries are kept. Commands call it (through check_output_file) before work.
void remove_dead_temporaries(const std::string& path);

// Writes `contents` to `path` atomically.
void write_file_atomically(const std::string& path, std::string_view contents);

}  // namespace splatcl
