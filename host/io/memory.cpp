#include "io/memory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/error.hpp"

namespace splatcl {
namespace {

namespace fs = std::filesystem;

// `room` becomes the smaller of it and `other`, where either is known.
void keep_smaller(std::optional<std::uint64_t>& room, std::optional<std::uint64_t> other) {
  if (other) room = room ? std::min(*room, *other) : *other;
}

std::optional<std::uint64_t> read_number(const fs::path& path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return std::nullopt;  // "max"
  return std::strtoull(text.c_str(), nullptr, 10);
}

// A "key value" line of a cgroup's memory.stat (0 when absent).
std::uint64_t stat_field(const fs::path& path, const std::string& key) {
  std::ifstream in(path);
  std::string name;
  std::uint64_t value = 0;
  while (in >> name >> value)
    if (name == key) return value;
  return 0;
}

// What one cgroup folder's limit leaves: limit − (usage − inactive page cache, which the kernel
// reclaims before it kills: a batch run's reads and writes fill it up to the limit), where a limit
// is set. v2 names memory.max and memory.current; v1 memory.limit_in_bytes and usage_in_bytes.
std::optional<std::uint64_t> room_in(const fs::path& dir, bool v2) {
  auto limit = read_number(dir / (v2 ? "memory.max" : "memory.limit_in_bytes"));
  const auto usage = read_number(dir / (v2 ? "memory.current" : "memory.usage_in_bytes"));
  if (!v2) {  // a v1 limit may be set higher up the hierarchy
    const std::uint64_t hierarchical = stat_field(dir / "memory.stat", "hierarchical_memory_limit");
    if (hierarchical > 0 && (!limit || hierarchical < *limit)) limit = hierarchical;
  }
  if (!limit || !usage || *limit >= (std::uint64_t{1} << 60)) return std::nullopt;
  const std::uint64_t inactive = stat_field(dir / "memory.stat", v2 ? "inactive_file" : "total_inactive_file");
  const std::uint64_t used = *usage > inactive ? *usage - inactive : 0;
  return *limit > used ? *limit - used : 0;
}

}  // namespace

std::optional<std::uint64_t> cgroup_memory_room(const std::string& self_cgroup, const std::string& mount) {
  std::optional<std::uint64_t> room;
  std::istringstream in(self_cgroup);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find(':'), second = first == std::string::npos ? first : line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string controllers = "," + line.substr(first + 1, second - first - 1) + ",";
    const fs::path relative = fs::path(line.substr(second + 1)).relative_path();
    const bool v2 = line.compare(0, first, "0") == 0 && controllers == ",,";
    if (!v2 && controllers.find(",memory,") == std::string::npos) continue;
    const fs::path root = v2 ? fs::path(mount) : fs::path(mount) / "memory";
    std::error_code error;
    fs::path dir = relative.empty() ? root : root / relative;
    if (!fs::is_directory(dir, error)) dir = root;
    for (;; dir = dir.parent_path()) {
      keep_smaller(room, room_in(dir, v2));
      if (!v2 || dir == root || !dir.has_relative_path()) break;  // v1's hierarchical limit covers the parents
    }
  }
  return room;
}

std::string memory_size(std::uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (bytes >= (1ull << 30)) return fmt::format("{:.2f} GiB", b / (1ull << 30));
  if (bytes >= (1ull << 20)) return fmt::format("{:.0f} MiB", b / (1ull << 20));
  if (bytes >= (1ull << 10)) return fmt::format("{:.0f} KiB", b / (1ull << 10));
  return fmt::format("{} bytes", bytes);
}

std::string proc_field(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size(), key) != 0) continue;
    const auto colon = line.find(':', key.size());
    if (colon == std::string::npos) continue;
    const auto begin = line.find_first_not_of(" \t", colon + 1);
    return begin == std::string::npos ? std::string{} : line.substr(begin);
  }
  return {};
}

std::optional<std::uint64_t> proc_kib(const char* file, const std::string& key) {
  const std::string value = proc_field(file, key);
  if (value.empty() || !std::isdigit(static_cast<unsigned char>(value[0]))) return std::nullopt;
  return std::strtoull(value.c_str(), nullptr, 10) * 1024;
}

std::optional<std::uint64_t> memory_limit_from_environment() {
  const char* text = std::getenv("SPLATCL_MEMORY_LIMIT");
  if (!text || !*text) return std::nullopt;
  const std::string value(text);
  std::size_t digits = 0;
  while (digits < value.size() && std::isdigit(static_cast<unsigned char>(value[digits]))) ++digits;
  const std::string suffix = value.substr(digits);
  const std::string units = "KMGT";
  const auto unit = suffix.size() == 1 ? units.find(static_cast<char>(std::toupper(static_cast<unsigned char>(suffix[0])))) : std::string::npos;
  if (digits == 0 || digits > 12 || !(suffix.empty() || unit != std::string::npos))
    throw Error(fmt::format("SPLATCL_MEMORY_LIMIT '{}' is not a byte count (digits, optionally followed by K, M, G or T)", value));
  const std::uint64_t number = std::strtoull(value.c_str(), nullptr, 10);
  const unsigned shift = suffix.empty() ? 0 : 10 * static_cast<unsigned>(unit + 1);
  if (number > (UINT64_MAX >> shift)) throw Error(fmt::format("SPLATCL_MEMORY_LIMIT '{}' is beyond 16 EiB", value));
  return number << shift;
}

std::optional<std::uint64_t> available_memory() {
  std::optional<std::uint64_t> room = proc_kib("/proc/meminfo", "MemAvailable");
  std::ifstream self("/proc/self/cgroup");
  std::stringstream text;
  text << self.rdbuf();
  keep_smaller(room, cgroup_memory_room(text.str(), "/sys/fs/cgroup"));
  if (const auto limit = memory_limit_from_environment()) {
    const std::uint64_t held = proc_kib("/proc/self/status", "VmRSS").value_or(0);
    keep_smaller(room, *limit > held ? *limit - held : 0);
  }
  return room;
}

void require_memory(std::uint64_t bytes, const std::string& what, const std::string& remedy) {
  const auto room = available_memory();
  if (!room || bytes <= *room) return;
  const char* limit = std::getenv("SPLATCL_MEMORY_LIMIT");
  throw Error(fmt::format("{} needs about {} more memory, and {} is available{}: {}", what, memory_size(bytes), memory_size(*room),
                          limit && *limit ? " within SPLATCL_MEMORY_LIMIT" : "", remedy));
}

}  // namespace splatcl
