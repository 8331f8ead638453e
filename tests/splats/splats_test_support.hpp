#pragma once
// Shared by the splat tests: one Runtime per process, generated meshes, and the shared models.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "runtime/runtime.hpp"
#include "splats/mesh.hpp"

namespace splatcl::splats::testing {

inline Runtime& runtime() {
  static const std::shared_ptr<Runtime> instance = Runtime::create();
  return *instance;
}

// A shared model from ../shared/data/models, or "" when that folder is not beside the checkout.
inline std::string model_path(const std::string& name) {
  const std::string path = std::string(SPLATCL_MODELS_DIR) + "/" + name;
  return std::filesystem::exists(path) ? path : std::string();
}

// A flat square [0, size]² in z = 0, split into cells × cells quads.
inline Mesh plane_mesh(unsigned cells, float size = 1.0f) {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  for (unsigned y = 0; y <= cells; ++y)
    for (unsigned x = 0; x <= cells; ++x)
      vertices.push_back({size * static_cast<float>(x) / static_cast<float>(cells), size * static_cast<float>(y) / static_cast<float>(cells), 0.0f});
  for (unsigned y = 0; y < cells; ++y)
    for (unsigned x = 0; x < cells; ++x) {
      const std::uint32_t a = y * (cells + 1) + x;
      faces.push_back({a, a + 1, a + cells + 2, a + cells + 1});
    }
  return make_mesh(vertices, faces, "plane");
}

// A UV sphere of radius r: smooth, curved everywhere.
inline Mesh sphere_mesh(unsigned rings, unsigned segments, float r = 1.0f) {
  std::vector<Vec3> vertices{{0, 0, r}};
  std::vector<std::vector<std::uint32_t>> faces;
  for (unsigned i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (unsigned j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * j / segments;
      vertices.push_back({static_cast<float>(r * std::sin(theta) * std::cos(phi)), static_cast<float>(r * std::sin(theta) * std::sin(phi)),
                          static_cast<float>(r * std::cos(theta))});
    }
  }
  vertices.push_back({0, 0, -r});
  const auto at = [&](unsigned ring, unsigned j) { return 1 + (ring - 1) * segments + j % segments; };
  const std::uint32_t south = static_cast<std::uint32_t>(vertices.size() - 1);
  for (unsigned j = 0; j < segments; ++j) faces.push_back({0, at(1, j), at(1, j + 1)});
  for (unsigned i = 1; i + 1 < rings; ++i)
    for (unsigned j = 0; j < segments; ++j) faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  for (unsigned j = 0; j < segments; ++j) faces.push_back({at(rings - 1, j), south, at(rings - 1, j + 1)});
  return make_mesh(vertices, faces, "sphere");
}

// An axis-aligned cube [0, 1]³ of six quads: hard 90° edges.
inline Mesh cube_mesh() {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  return make_mesh(v, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}}, "cube");
}

}  // namespace splatcl::splats::testing
