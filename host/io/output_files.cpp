#include "io/output_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/image_codec.hpp"
#include "io/in_flight.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace fs = std::filesystem;

void check_writable_directory(const std::string& dir, const std::string& what) {
  const std::string probe = (fs::path(dir) / (".splatcl-write-test" + std::to_string(::getpid()))).string();
  const auto fail = [&](int error) {
    ::unlink(probe.c_str());
    // The directory exists (callers check): ENOENT then comes from a file system that makes no new
    // files, such as /proc ("No such file or directory" named the wrong cause).
    const std::string cause = error == ENOENT ? "its file system does not take new files" : std::strerror(error);
    throw Error("cannot write " + what + ": directory " + dir + " is not writable (" + cause + ")");
  };
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(errno);
  const char byte = 0;
  const bool written = ::write(fd, &byte, 1) == 1;
  const int write_error = errno;
  if (::close(fd) != 0 || !written) fail(written ? errno : write_error);
  ::unlink(probe.c_str());
}

fs::path check_output_path(const std::string& path, const std::string& what) {
  if (path.empty()) return {};
  const std::string name = "cannot write " + what + " " + path + ": ";
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(name + "it is a directory");
  const fs::path target(written_through(path));
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Error(name + (fs::exists(dir, ec) ? dir.string() + " is a file, not a directory" : "directory " + dir.string() + " does not exist"));
  // The longest name written for it: a staged output's NAME.partialPID.EXT.tmpPID (io/atomic_file.hpp).
  // Too long, it failed with "File name too long" only when written, after the work (a batch
  // model with a 248-byte id).
  const long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  const std::size_t bytes = target.filename().string().size(), more = kTemporaryNameBytes + fs::path(path).extension().string().size();
  if (name_max > 0 && bytes + more > static_cast<std::size_t>(name_max))
    throw Error(name + fmt::format("the file name is {} bytes long; this file system allows {}, and splatcl's temporary names add {}",
                                   bytes, name_max, more));
  return dir;
}

void check_output_file(const std::string& path, const std::string& what) {
  if (path.empty()) return;
  const fs::path dir = check_output_path(path, what);
  check_writable_directory(dir.string(), what + " " + path);
  check_image_module(path, "cannot write " + what + " " + path + ": ");
  remove_dead_temporaries(path);
}

fs::path comparable_path(const std::string& path) {
  std::error_code ec;
  std::string through = path;
  try {
    through = written_through(path);  // weakly_canonical stops at a dangling link
  } catch (const Error&) {
    // A loop of links is compared as given; writing it fails, naming the loop.
  }
  fs::path p = fs::absolute(through, ec);
  if (!ec) p = fs::weakly_canonical(p, ec);  // absolute first: a relative name whose first part does not exist stays relative
  if (ec) p = fs::path(through).lexically_normal();
  // "P/" names what "P" names: a trailing separator of a path that does not exist yet stays
  // (render --json P --cache P/ passed the distinct-outputs check).
  while (!p.has_filename() && p.has_relative_path()) p = p.parent_path();
  return p;
}

bool path_within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty() && std::next(o) == outer.end()) break;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

void check_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::vector<std::pair<std::string, fs::path>> seen;  // option, normalised absolute path
  for (const auto& [option, path] : outputs) {
    if (path.empty()) continue;
    const fs::path p = comparable_path(path);
    for (const auto& [other, q] : seen)
      if (q == p) throw Error(other + " and " + option + " name the same file " + path);
    seen.emplace_back(option, p);
  }
}

void check_outputs_spare_inputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                                const std::vector<std::pair<std::string, std::string>>& inputs) {
  for (const auto& [option, path] : outputs) {
    if (path.empty()) continue;
    const fs::path p = comparable_path(path);
    for (const auto& [what, input] : inputs)
      if (!input.empty() && comparable_path(input) == p) throw Error(fmt::format("{} {} would overwrite the {} {}", option, path, what, input));
  }
}

std::string output_extension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void check_output_extension(const std::string& path, const std::string& option, const std::vector<std::string>& extensions,
                            const std::string& holds) {
  if (path.empty()) return;
  const std::string extension = output_extension(path);
  if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) return;
  std::string list;
  for (const std::string& e : extensions) list += (list.empty() ? "" : " or ") + e;
  throw Error(fmt::format("{} {}: the file must end in {} ({})", option, path, list, holds));
}

StagedOutputs::~StagedOutputs() {
  for (std::size_t i = committed_; i < entries_.size(); ++i) {
    std::error_code ignored;
    fs::remove(entries_[i].staged, ignored);
    unregister_in_flight(entries_[i].in_flight);
  }
}

std::string StagedOutputs::stage(const std::string& path) {
  // The pid keeps concurrent runs writing the same target apart; through a link, beside its file.
  const std::string through = written_through(path);
  const std::string staged = through + ".partial" + std::to_string(::getpid()) + fs::path(path).extension().string();
  entries_.push_back({path, through, staged, register_in_flight(staged)});
  return staged;
}

void StagedOutputs::write(const std::string& path, const std::function<void(const std::string& staged)>& write) {
  const Entry* entry = nullptr;
  for (const Entry& e : entries_)
    if (e.target == path) entry = &e;
  if (!entry) throw Error("cannot write " + path + ": it was not staged");
  try {
    write(entry->staged);
  } catch (const Error& e) {
    std::string message = e.what();
    for (std::size_t at; (at = message.find(entry->staged)) != std::string::npos;) message.replace(at, entry->staged.size(), path);
    throw Error(message);
  }
}

void StagedOutputs::commit() {
  for (; committed_ < entries_.size(); ++committed_) {
    const Entry& e = entries_[committed_];
    std::error_code ec;
    if (!fs::is_regular_file(e.staged, ec)) throw Error("cannot write " + e.target + ": it was never written");
    fs::rename(e.staged, e.through, ec);
    if (ec) throw Error("cannot write " + e.target + ": " + ec.message());
    unregister_in_flight(e.in_flight);
  }
}

}  // namespace splatcl
