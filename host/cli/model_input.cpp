#include "cli/model_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "io/json_keys.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli {
namespace {

std::vector<std::string>& pending_warnings() {
  static std::vector<std::string> warnings;
  return warnings;
}

}  // namespace

Mesh load_model(const std::string& path, ProgressLine& progress, Winding winding, bool strict) {
  progress.show("loading " + path);
  Mesh mesh = load_mesh(path, winding);
  if (mesh.problems.any()) {
    if (strict) throw Error(fmt::format("{}: {} (--strict)", path, mesh.problems.summary()));
    pending_warnings().push_back(fmt::format("splatcl: warning: {}: {}", path, mesh.problems.summary()));
  }
  // Vertices are floats: far from the origin for its size a mesh loses its detail on reading (a unit
  // sphere at 1e7 became a handful of points 1 apart, and csm built from it without a word).
  const Box box = mesh.bounds();
  // The spacing of floats where the mesh reaches (|x| 2^-24, half of it at most, was printed as the step).
  const double reach = box.reach(), diagonal = box.exact_diagonal();
  const double step = reach > 0 && std::isfinite(reach) ? std::ldexp(1.0, std::max(std::ilogb(reach), -126) - 23) : 0.0;
  if (diagonal > 0 && step > kFloatStepWarning * diagonal)
    pending_warnings().push_back(fmt::format("splatcl: warning: {}: coordinates reach {:.7g}, where floats step by {:.3g} ({:.2g} % of the "
                                             "mesh's {:.4g} diagonal): detail finer than that was lost on reading; translate the mesh "
                                             "nearer the origin",
                                             path, box.reach(), step, 100 * step / diagonal, diagonal));
  return mesh;
}

void print_model_warnings() {
  std::fflush(stdout);
  for (const auto& line : pending_warnings()) std::fprintf(stderr, "%s\n", printable(line).c_str());
  pending_warnings().clear();
}

}  // namespace splatcl::cli
