#pragma once
// The test models: the folder SPLATCL_MODELS_DIR, which the test program defines (data/models by
// default, or the models' folder CI keeps beside the checkout). Tests that need one skip when it is
// absent.
#include <filesystem>
#include <string>

namespace splatcl::testing {

// The path of the test model `name` ("stanford-bunny.obj"), or "" when it is absent.
inline std::string model_path(const std::string& name) {
  // Joined as a path: GCC 12 warns falsely (-Warray-bounds) on `std::string(...) + "/" + name` once
  // it is inlined into a unity batch of tests.
  const std::string path = (std::filesystem::path(SPLATCL_MODELS_DIR) / name).string();
  return std::filesystem::exists(path) ? path : std::string();
}

}  // namespace splatcl::testing
