#include "io/memory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>

#include "runtime/error.hpp"

namespace splatcl {
namespace {

std::optional<std::uint64_t> read_number(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return std::nullopt;  // "max"
  return std::strtoull(text.c_str(), nullptr, 10);
}

std::optional<std::uint64_t> kib_field(const char* file, const char* key) {
  const std::string value = proc_field(file, key);
  if (value.empty() || !std::isdigit(static_cast<unsigned char>(value[0]))) return std::nullopt;
  return std::strtoull(value.c_str(), nullptr, 10) * 1024;
}

// What a cgroup's limit leaves: limit − usage, where the limit is below the machine's memory.
std::optional<std::uint64_t> cgroup_room() {
  for (const auto& [limit_path, usage_path] : {std::pair{"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"},
                                               std::pair{"/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                                         "/sys/fs/cgroup/memory/memory.usage_in_bytes"}}) {
    const auto limit = read_number(limit_path), usage = read_number(usage_path);
    if (limit && usage && *limit < (std::uint64_t{1} << 60)) return *limit > *usage ? *limit - *usage : 0;
  }
  return std::nullopt;
}

}  // namespace

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
  std::optional<std::uint64_t> room = kib_field("/proc/meminfo", "MemAvailable");
  const auto tighter = [&](std::optional<std::uint64_t> other) {
    if (other) room = room ? std::min(*room, *other) : *other;
  };
  tighter(cgroup_room());
  if (const auto limit = memory_limit_from_environment()) {
    const std::uint64_t held = kib_field("/proc/self/status", "VmRSS").value_or(0);
    tighter(*limit > held ? *limit - held : 0);
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
