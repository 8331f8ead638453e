// .csm files (csm/csm_file.hpp). Each input is read twice: as it is, and resealed (its checksum
// field set to the checksum of its bytes), so that mutations get past the checksum to the checks
// behind it. A file that decodes must survive a round trip in both encodings: encoding what was
// read and decoding it again gives the same bytes when encoded once more.
#include <cstring>

#include "csm/csm_file.hpp"
#include "fuzz_reader.hpp"
#include "io/checksum.hpp"

namespace {

void read_csm(const std::string& bytes) {
  using namespace splatcl::csm;
  const Csm csm = decode_csm(bytes, "fuzz.csm");
  for (const Encoding encoding : {Encoding::Plain, Encoding::Compact}) {
    const std::string encoded = encode_csm(csm, encoding);
    Encoding read_back = Encoding::Plain;
    if (encode_csm(decode_csm(encoded, "fuzz.csm re-encoded", &read_back), encoding) != encoded || read_back != encoding)
      splatcl::fuzz::finding(std::string("a decoded .csm does not survive a round trip in the ") + to_string(encoding) + " encoding");
  }
}

// The checksum (u64 at byte 204, docs/formats.md) of the header with that field zero, then the rest.
std::string resealed(std::string bytes) {
  constexpr std::size_t kChecksumOffset = 204;
  if (bytes.size() < splatcl::csm::kCsmHeaderBytes) return bytes;
  std::memset(bytes.data() + kChecksumOffset, 0, 8);
  const std::uint64_t hash = splatcl::fnv1a64(bytes);
  std::memcpy(bytes.data() + kChecksumOffset, &hash, 8);
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader_and_resealed(data, size, "fuzz.csm", read_csm, resealed);
  return 0;
}
