#pragma once
// Content checksums for change detection (resumable batch runs, output verification): 64-bit
// FNV-1a, printed as 16 lowercase hex digits. Not a cryptographic hash: it detects edits and
// corruption, not deliberate collisions.
#include <cstdint>
#include <string>
#include <string_view>

namespace splatcl {

inline constexpr std::uint64_t kFnv1aBasis = 0xcbf29ce484222325ull;

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t hash = kFnv1aBasis);

// "%016x" of a checksum.
std::string checksum_hex(std::uint64_t checksum);

// Checksum of a string's bytes, as hex.
std::string checksum_of(std::string_view bytes);

// Checksum of a file's bytes, as hex, read in blocks (memory stays small for large meshes).
// Throws Error naming the file when it cannot be read. `bytes` receives the file size when given.
std::string checksum_of_file(const std::string& path, std::uint64_t* bytes = nullptr);

}  // namespace splatcl
