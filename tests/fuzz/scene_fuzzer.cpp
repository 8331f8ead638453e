// Scenes (core/scene.hpp), as `render`, `view` and `cluster` read them (meshes are not loaded).
#include "fuzz_reader.hpp"
#include "core/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader(data, size, "fuzz-scene.json",
                              [](const std::string& bytes) { splatcl::parse_scene(bytes, "fuzz-scene.json", "."); });
  return 0;
}
