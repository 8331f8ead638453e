// Splat PLY files (splats/splat_file.hpp), as `splats verify`, `render` and the asset cache read
// them. Each input is read twice: as it is, and resealed (the 16 digits after `comment
// splatcl_checksum ` set to the checksum of the file with those digits zero, docs/formats.md), so
// that mutations get past the checksum to the header and splat checks behind it.
#include "fuzz_reader.hpp"
#include "io/checksum.hpp"
#include "splats/splat_file.hpp"

namespace {

void read_splats(const std::string& bytes) { splatcl::splats::decode_splat_file(bytes, "fuzz.ply"); }

std::string resealed(std::string bytes) {
  const std::string key = "\ncomment splatcl_checksum ";
  const std::size_t end = bytes.find("end_header\n"), at = bytes.find(key);
  if (end == std::string::npos || at == std::string::npos || at + key.size() + 16 > end) return bytes;
  const std::size_t digits = at + key.size();
  bytes.replace(digits, 16, "0000000000000000");
  bytes.replace(digits, 16, splatcl::checksum_hex(splatcl::fnv1a64(bytes)));
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader_and_resealed(data, size, "fuzz.ply", read_splats, resealed);
  return 0;
}
