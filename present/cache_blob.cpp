#include "present/cache_blob.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <string_view>

#include "io/atomic_file.hpp"
#include "io/checksum.hpp"
#include "runtime/error.hpp"

namespace splatcl::present {

void write_cache_blob(const std::string& path, const CacheMagic& magic, std::uint32_t version,
                      const std::vector<std::uint32_t>& counts, const std::string& body) {
  std::string file(magic, 8);
  file.append(reinterpret_cast<const char*>(&version), 4);
  put_array(file, counts);
  const std::uint64_t checksum = fnv1a64(body, fnv1a64(file));
  file.append(reinterpret_cast<const char*>(&checksum), 8);
  write_file_atomically(path, file + body);
}

CacheBlob read_cache_blob(const std::string& path, const CacheMagic& magic, std::uint32_t version, std::size_t count_fields,
                          const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  CacheBlob blob;
  blob.path = path;
  blob.bytes = std::move(buffer).str();
  const std::string& file = blob.bytes;
  const auto fail = [&](const std::string& why) { return Error(path + ": " + why); };
  const std::size_t header = 8 + 4 + 4 * count_fields, header_bytes = header + 8;
  if (file.size() < header_bytes || std::memcmp(file.data(), magic, 8) != 0) throw fail(fmt::format("not a splatcl {}", what));
  std::uint32_t file_version = 0;
  std::memcpy(&file_version, file.data() + 8, 4);
  if (file_version != version) throw fail(fmt::format("{} version {} is not {}", what, file_version, version));
  blob.counts.resize(count_fields);
  std::memcpy(blob.counts.data(), file.data() + 12, 4 * count_fields);
  std::uint64_t checksum = 0;
  std::memcpy(&checksum, file.data() + header, 8);
  const std::string_view body(file.data() + header_bytes, file.size() - header_bytes);
  if (checksum != fnv1a64(body, fnv1a64(std::string_view(file.data(), header)))) throw fail("checksum mismatch");
  blob.at = header_bytes;
  return blob;
}

void cache_blob_truncated(const std::string& path) { throw Error(path + ": truncated"); }

void CacheBlob::expect_consumed() const {
  if (at != bytes.size()) throw Error(path + ": oversized");
}

}  // namespace splatcl::present
