// ao_vs_raycast MESH CSM [LIFT]: the self-AO error of a CSM (docs/results/csm.md). AO at every
// vertex of MESH under its own CSM (the native reference, default sampling of `splatcl ao`, the
// receivers lifted LIFT texels, default 1 as `splatcl ao --lift`) against ray casting the same
// directions at the mesh itself; prints the mean absolute difference and the share of vertices off
// by more than 0.05. A measurement tool, not a test.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>

#include "csm/ao_receivers.hpp"
#include "csm/csm_file.hpp"
#include "core/mesh.hpp"

int main(int argc, char** argv) {
  using namespace splatcl::csm;
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: ao_vs_raycast MESH CSM [LIFT_TEXELS]\n");
    return 2;
  }
  try {
    const splatcl::Mesh mesh = splatcl::load_mesh(argv[1]);
    const Csm csm = read_csm(argv[2]);
    ReceiverAoOptions options;
    options.lift = receiver_lifts(mesh, {&csm}, {{0, kIdentity}}, argc == 4 ? std::stof(argv[3]) : kDefaultLiftTexels);
    const std::vector<splatcl::Vec4> with_csm = receiver_ambient_occlusion(mesh, VisibilityScene({&csm}, {{0, kIdentity}}), options, nullptr);
    const std::vector<float> by_rays = raycast_ambient_occlusion(mesh, mesh, options);
    double error = 0, mean_csm = 0, mean_rays = 0;
    std::size_t off = 0;
    for (std::size_t v = 0; v < by_rays.size(); ++v) {
      const double d = std::abs(static_cast<double>(with_csm[v].w) - by_rays[v]);
      error += d;
      off += d > 0.05;
      mean_csm += with_csm[v].w;
      mean_rays += by_rays[v];
    }
    const auto n = static_cast<double>(by_rays.size());
    fmt::print("{} vertices, {} directions each: mean AO {:.4f} (CSM) vs {:.4f} (rays); mean |difference| {:.4f}; "
               "{} vertices ({:.1f} %) off by more than 0.05\n",
               by_rays.size(), options.samples, mean_csm / n, mean_rays / n, error / n, off, 100.0 * static_cast<double>(off) / n);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ao_vs_raycast: %s\n", e.what());
    return 1;
  }
}
