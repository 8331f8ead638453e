#include "io/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "io/in_flight.hpp"
#include "runtime/error.hpp"

namespace splatcl {

std::string written_through(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p(path);
  // Linux follows at most 40 links in a path.
  for (int links = 0; links < 40; ++links) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p.string();
    const fs::path next = fs::read_symlink(p, ec);
    if (ec) throw Error("cannot write " + path + ": " + ec.message());
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  throw Error("cannot write " + path + ": too many levels of symbolic links");
}

void write_atomically(const std::string& path, const std::function<void(const std::string& temp_path)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(written_through(path));
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw Error("cannot write " + path + ": directory " + dir.string() + " does not exist");
  // The pid keeps concurrent writers of the same target apart.
  const std::string temp = target.string() + ".tmp" + std::to_string(::getpid());
  // Removed by a terminating signal while it exists (io/in_flight.hpp).
  struct InFlight {
    int slot;
    ~InFlight() { unregister_in_flight(slot); }
  } in_flight{register_in_flight(temp)};
  try {
    write(temp);
    if (const char* pause = std::getenv(kPauseBeforeRenameVariable)) std::this_thread::sleep_for(std::chrono::milliseconds(std::atol(pause)));
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw Error("cannot write " + path + ": " + ec.message());
  } catch (const Error&) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw Error("cannot write " + path + ": " + e.what());
  }
}

void remove_dead_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path target(path);
  try {
    target = written_through(path);
  } catch (const Error&) {
    return;  // a loop of links has no temporaries; writing it names the loop
  }
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string name = target.filename().string();
  if (name.empty()) return;
  std::error_code ec;
  std::vector<fs::path> dead;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (entry.size() <= name.size() || entry.compare(0, name.size(), name) != 0) continue;
    std::string_view rest = std::string_view(entry).substr(name.size());
    if (rest.starts_with(".tmp")) rest.remove_prefix(4);
    else if (rest.starts_with(".partial")) rest.remove_prefix(8);
    else continue;
    const std::size_t digits = std::min(rest.find_first_not_of("0123456789"), rest.size());
    if (digits == 0 || digits > 9) continue;
    std::string_view after = rest.substr(digits);
    // Staged names keep the extension as given, which differs from the file's through a link.
    const std::string extensions[] = {target.extension().string(), fs::path(path).extension().string()};
    for (const std::string& extension : extensions)
      if (!extension.empty() && after.starts_with(extension)) {
        after.remove_prefix(extension.size());
        break;
      }
    // A staged output is itself written atomically (NAME.partialPID.EXT.tmpPID, one process): kill -9
    // while it was being written left that temporary behind.
    if (after.starts_with(".tmp") && after.size() > 4 &&
        after.find_first_not_of("0123456789", 4) == std::string_view::npos)
      after = {};
    if (!after.empty()) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(std::string(rest.substr(0, digits))));
    if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) dead.push_back(it->path());
  }
  for (const auto& p : dead) fs::remove(p, ec);
}

void write_file_atomically(const std::string& path, std::string_view contents) {
  write_atomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write " + path + ": " + std::strerror(errno));
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    if (!out) throw Error("cannot write " + path + ": write failed (disk full?)");
  });
}

}  // namespace splatcl
