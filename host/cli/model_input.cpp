#include "cli/model_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "io/json_keys.hpp"
#include "runtime/error.hpp"
#include "splats/pipeline_options.hpp"

namespace splatcl::cli {
namespace {

std::vector<std::string>& pending_warnings() {
  static std::vector<std::string> warnings;
  return warnings;
}

}  // namespace

Mesh load_model(const std::string& path, ProgressLine& progress, Winding winding, bool strict, const ModelOrigin& origin) {
  progress.show("loading " + path);
  Mesh mesh = origin.kind == ModelOrigin::CentreWhen ? load_mesh_recentred(path, winding, origin.when)
              : origin.kind == ModelOrigin::Given    ? load_mesh_about(path, winding, origin.given)
                                                     : load_mesh(path, winding);
  if (mesh.problems.any()) {
    if (strict) throw Error(fmt::format("{}: {} (--strict)", path, mesh.problems.summary()));
    queue_warning(path, mesh.problems.summary());
  }
  if (const std::string far = float_step_warning(mesh); !far.empty()) queue_warning(path, far);
  if (origin.kind == ModelOrigin::CentreWhen)
    if (const std::string moved = splats::recentred_warning(mesh); !moved.empty()) queue_warning(path, moved);
  return mesh;
}

void queue_warning(const std::string& subject, const std::string& text) {
  pending_warnings().push_back(fmt::format("splatcl: warning: {}: {}", subject, text));
}

void print_model_warnings() {
  std::fflush(stdout);
  for (const auto& line : pending_warnings()) std::fprintf(stderr, "%s\n", printable(line).c_str());
  pending_warnings().clear();
}

}  // namespace splatcl::cli
