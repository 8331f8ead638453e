// Cluster scenes (cluster/test_scene.hpp), as `splatcl cluster SCENE.json` reads them.
#include "cluster/test_scene.hpp"
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader(data, size, "fuzz-scene.json",
                              [](const std::string& bytes) { splatcl::cluster::parse_scene(bytes, "fuzz-scene.json"); });
  return 0;
}
