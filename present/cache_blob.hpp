#pragma once
// The presenter's binary cache files of raw records (the LOD tree, the drawn splats' fit, the
// normal fields): an
// 8-byte magic, a u32 version, u32 counts, the FNV-1a 64 checksum of those header bytes and the
// body, then the body. Written atomically; read back with the magic, version and checksum checked.
// Raw records hold this build's struct layout: the cache keys name the format, and a file that
// does not check out is rebuilt (present/assets.cpp).
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace splatcl::present {

using CacheMagic = char[8];

void write_cache_blob(const std::string& path, const CacheMagic& magic, std::uint32_t version,
                      const std::vector<std::uint32_t>& counts, const std::string& body);

struct CacheBlob {
  std::string path;
  std::vector<std::uint32_t> counts;
  std::string bytes;   // the whole file; the body starts past the header
  std::size_t at = 0;  // read position in bytes (take), at the body's start after reading

  // The next n records of T from the body into v; Error when the body is shorter.
  template <class T>
  void take(std::vector<T>& v, std::size_t n);
  void expect_consumed() const;  // Error when bytes are left
};

// Throws Error naming `path` and the cause ("not a splatcl <what>", version, checksum).
CacheBlob read_cache_blob(const std::string& path, const CacheMagic& magic, std::uint32_t version, std::size_t count_fields,
                          const char* what);

template <class T>
void put_array(std::string& out, const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

void cache_blob_truncated(const std::string& path);  // throws Error

template <class T>
void CacheBlob::take(std::vector<T>& v, std::size_t n) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (n > (bytes.size() - at) / sizeof(T)) cache_blob_truncated(path);
  v.resize(n);
  if (n > 0) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
  at += n * sizeof(T);
}

}  // namespace splatcl::present
