#pragma once
// Shared by the splat tests: one Runtime per process, generated meshes, and the test models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "runtime/test_models.hpp"
#include "runtime/test_runtime.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"

namespace splatcl::splats::testing {

inline Runtime& runtime() { return splatcl::testing::shared_runtime(); }

// A path in the system's temporary folder for this test's file `name` ("cube.obj").
inline std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("splatcl-splats-" + name)).string();
}
// temp_path(name), written with `contents` (bytes as they are).
inline std::string temp_file(const std::string& name, const std::string& contents) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

using splatcl::testing::model_path;

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

// The cube with every face wound the other way: its normals point inwards.
inline Mesh inside_out_cube_mesh() {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  return make_mesh(v, {{1, 2, 3, 0}, {7, 6, 5, 4}, {4, 5, 1, 0}, {6, 7, 3, 2}, {5, 6, 2, 1}, {3, 7, 4, 0}}, "inside-out cube");
}

// An icosahedron subdivided `levels` times onto the unit sphere: 20 · 4^levels flat faces.
inline Mesh icosphere_mesh(unsigned levels) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Vec3> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::vector<std::uint32_t>> f{{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                            {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Vec3& p : v) p = normalized(p);
  for (unsigned level = 0; level < levels; ++level) {
    std::vector<std::vector<std::uint32_t>> next;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back(normalized(0.5f * (v[a] + v[b])));
      return middle[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    for (const auto& tri : f) {
      const std::uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
      next.push_back({tri[0], a, c}), next.push_back({tri[1], b, a}), next.push_back({tri[2], c, b}), next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  return make_mesh(v, f, "icosphere");
}

// A closed prism over a house-shaped pentagon: creases of 90°, 135° and a 105° ridge, flat faces
// (a fandisk-like CAD part).
inline Mesh creased_part_mesh() {
  const float profile[5][2] = {{0, 0}, {1, 0}, {1, 0.6f}, {0.5f, 0.95f}, {0, 0.6f}};
  std::vector<Vec3> v;
  for (const float z : {0.0f, 0.8f})
    for (const auto& p : profile) v.push_back({p[0], p[1], z});
  std::vector<std::vector<std::uint32_t>> f{{4, 3, 2, 1, 0}, {5, 6, 7, 8, 9}};
  for (std::uint32_t i = 0; i < 5; ++i) f.push_back({i, (i + 1) % 5, (i + 1) % 5 + 5, i + 5});
  return make_mesh(v, f, "creased part");
}

// A closed box of thickness `thickness` over the unit square: two sheets facing away from each
// other, closer than a few ε.
inline Mesh thin_shell_mesh(float thickness) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, thickness}, {1, 0, thickness}, {1, 1, thickness}, {0, 1, thickness}};
  return make_mesh(v, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}}, "thin shell");
}

// A planar disk of `count` sliver triangles fanned around its centre.
inline Mesh sliver_fan_mesh(unsigned count) {
  std::vector<Vec3> v{{0, 0, 0}};
  std::vector<std::vector<std::uint32_t>> f;
  for (unsigned i = 0; i < count; ++i) {
    const double angle = 2 * std::numbers::pi * i / count;
    v.push_back({static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)), 0});
  }
  for (std::uint32_t i = 0; i < count; ++i) f.push_back({0, 1 + i, 1 + (i + 1) % count});
  return make_mesh(v, f, "sliver fan");
}

// A cells × cells grid of quads over the unit square whose corners alternate between z = 0 and
// z = height: every quad is non-planar.
inline Mesh non_planar_quads_mesh(unsigned cells, float height) {
  std::vector<Vec3> v;
  std::vector<std::vector<std::uint32_t>> f;
  for (unsigned y = 0; y <= cells; ++y)
    for (unsigned x = 0; x <= cells; ++x)
      v.push_back({static_cast<float>(x) / static_cast<float>(cells), static_cast<float>(y) / static_cast<float>(cells),
                   (x + y) % 2 ? height : 0.0f});
  for (unsigned y = 0; y < cells; ++y)
    for (unsigned x = 0; x < cells; ++x) {
      const std::uint32_t a = y * (cells + 1) + x;
      f.push_back({a, a + 1, a + cells + 2, a + cells + 1});
    }
  return make_mesh(v, f, "non-planar quads");
}

}  // namespace splatcl::splats::testing
