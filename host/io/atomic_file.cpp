#include "io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "runtime/error.hpp"

namespace splatcl {

void write_atomically(const std::string& path, const std::function<void(const std::string& temp_path)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw Error("cannot write " + path + ": directory " + dir.string() + " does not exist");
  // The pid keeps concurrent writers of the same target apart.
  const std::string temp = path + ".tmp" + std::to_string(::getpid());
  try {
    write(temp);
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
