#pragma once
// The splats and csm suites read the test models from splats_models_dir() (data/models by default);
// the models are not part of the repository, so the tests that run those suites skip without them.
#include <filesystem>
#include <string>
#include <vector>

#include "bench/suites.hpp"

namespace splatcl::bench {

// The first model the suite needs that is absent ("" when all are there, or the suite needs none).
inline std::string missing_bench_model(const std::string& suite) {
  std::vector<std::string> files;
  if (suite == "csm" || suite == "splats") files.push_back("stanford-bunny.obj");
  if (suite == "splats") files.push_back("ogre.obj");
  for (const std::string& file : files) {
    const std::filesystem::path path = std::filesystem::path(splats_models_dir()) / file;
    if (!std::filesystem::is_regular_file(path)) return path.string();
  }
  return {};
}

}  // namespace splatcl::bench
