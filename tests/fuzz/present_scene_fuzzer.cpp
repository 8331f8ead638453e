// Presenter scenes (present/scene.hpp), as `render` and `view` read them (meshes are not loaded).
#include "fuzz_reader.hpp"
#include "present/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splatcl::fuzz::check_reader(data, size, "fuzz-scene.json",
                              [](const std::string& bytes) { splatcl::present::parse_scene(bytes, "fuzz-scene.json", "."); });
  return 0;
}
