#include "io/checksum.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "runtime/error.hpp"

namespace splatcl {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

std::string checksum_hex(std::uint64_t checksum) { return fmt::format("{:016x}", checksum); }

std::string checksum_of(std::string_view bytes) { return checksum_hex(fnv1a64(bytes)); }

std::string checksum_of_file(const std::string& path, std::uint64_t* bytes) {
  // Opening a FIFO waits for a writer: refuse what is not a plain file before opening it.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw Error("cannot read " + path + ": not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path + ": " + std::strerror(errno));
  std::vector<char> block(1 << 20);
  std::uint64_t hash = kFnv1aBasis, total = 0;
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    hash = fnv1a64(std::string_view(block.data(), n), hash);
    total += n;
  }
  if (in.bad()) throw Error("cannot read " + path + ": read failed");
  if (bytes) *bytes = total;
  return checksum_hex(hash);
}

}  // namespace splatcl
