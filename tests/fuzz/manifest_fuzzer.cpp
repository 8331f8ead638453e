// Batch manifests (batch/manifest.hpp), JSON or CSV by SPLATCL_FUZZ_MANIFEST_CSV, with the defaults
// `splatcl batch` starts from; what a run then derives from the list (its checksum) is computed too.
#include "batch/manifest.hpp"
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splatcl::batch;
  const std::string name = SPLATCL_FUZZ_MANIFEST_CSV ? "fuzz-manifest.csv" : "fuzz-manifest.json";
  splatcl::fuzz::check_reader(data, size, name, [&](const std::string& bytes) {
    const std::vector<ModelEntry> models =
        SPLATCL_FUZZ_MANIFEST_CSV ? parse_csv_manifest(bytes, name, "models") : parse_json_manifest(bytes, name, "models");
    (void)manifest_checksum(models);
  });
  return 0;
}
