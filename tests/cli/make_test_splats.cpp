// make_test_splats DIR: splat files with a known truth for `splatcl splats verify` against the unit
// square [0, 1]² in z = 0 (eps 0.05 recorded): verify-good.ply covers it (a grid of circles of
// radius 0.045 at spacing 1/17, none leaving the square by more than 0.045); verify-lifted.ply adds
// a circle 3 eps above it; verify-hole.ply drops one circle of the grid, leaving a hole.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "splats/splat_file.hpp"

int main(int argc, char** argv) {
  using namespace splatcl::splats;
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_test_splats DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const float eps = 0.05f, radius = 0.045f;
  const unsigned intervals = 17;
  const auto circle = [&](float x, float y, float z) {
    SplatRecord s;
    s.center = {x, y, z}, s.normal = {0, 0, 1}, s.major = {radius, 0, 0}, s.minor = {0, radius, 0};
    return s;
  };
  std::vector<SplatRecord> good;
  for (unsigned y = 0; y <= intervals; ++y)
    for (unsigned x = 0; x <= intervals; ++x)
      good.push_back(circle(static_cast<float>(x) / intervals, static_cast<float>(y) / intervals, 0));
  std::vector<SplatRecord> lifted = good, hole = good;
  lifted.push_back(circle(0.5f, 0.5f, 3 * eps));
  hole.erase(hole.begin() + 8 * (intervals + 1) + 8);
  const SplatFileInfo info{"verify-plane.obj", "vertices", eps, 10, 255, "grey", false};
  try {
    write_splat_file(dir + "/verify-good.ply", good, info);
    write_splat_file(dir + "/verify-lifted.ply", lifted, info);
    write_splat_file(dir + "/verify-hole.ply", hole, info);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_test_splats: %s\n", e.what());
    return 1;
  }
  return 0;
}
