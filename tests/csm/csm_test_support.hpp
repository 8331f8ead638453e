#pragma once
// Shared by the CSM tests: one Runtime per process, small meshes made in code, the test models.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "runtime/test_models.hpp"
#include "runtime/test_runtime.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"
#include "csm/build.hpp"
#include "csm/visibility.hpp"

namespace splatcl::csm::testing {

using splatcl::Mesh;
using splatcl::Vec3;

inline Runtime& runtime() { return splatcl::testing::shared_runtime(); }

// A placement that moves by (x, y, z).
inline Transform translation(double x, double y, double z) { return {1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1}; }

using splatcl::testing::model_path;

// Axis-aligned closed boxes (outward quads), one mesh.
inline Mesh boxes_mesh(const std::vector<std::pair<Vec3, Vec3>>& boxes, const std::string& name = "boxes") {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  for (const auto& [lo, hi] : boxes) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    for (int k = 0; k < 8; ++k) vertices.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) faces.push_back({base + q[0], base + q[1], base + q[2], base + q[3]});
  }
  return make_mesh(vertices, faces, name);
}

inline Mesh cube_mesh() { return boxes_mesh({{{-1, -1, -1}, {1, 1, 1}}}, "cube"); }

// An open square in z = 0 (every hit is single-surface).
inline Mesh square_mesh() {
  return make_mesh({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 1, 2, 3}}, "square");
}

// An open wavy sheet over [-1, 1]² in cells × cells quads, y = 0.1 sin(3x) cos(2z): every hit is
// single-surface (the exact rule).
inline Mesh wavy_sheet_mesh(int cells) {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const float x = -1 + 2.0f * static_cast<float>(i) / static_cast<float>(cells), z = -1 + 2.0f * static_cast<float>(j) / static_cast<float>(cells);
      vertices.push_back({x, 0.1f * std::sin(3 * x) * std::cos(2 * z), z});
    }
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (cells + 1) + a); };
      faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  return make_mesh(vertices, faces, "wavy sheet");
}

// A closed UV sphere.
inline Mesh sphere_mesh(unsigned rings, unsigned segments, float r = 1.0f) {
  std::vector<Vec3> vertices{{0, r, 0}};
  std::vector<std::vector<std::uint32_t>> faces;
  for (unsigned i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (unsigned j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * j / segments;
      vertices.push_back({static_cast<float>(r * std::sin(theta) * std::cos(phi)), static_cast<float>(r * std::cos(theta)),
                          static_cast<float>(r * std::sin(theta) * std::sin(phi))});
    }
  }
  vertices.push_back({0, -r, 0});
  const auto at = [&](unsigned ring, unsigned j) { return 1 + (ring - 1) * segments + j % segments; };
  const auto south = static_cast<std::uint32_t>(vertices.size() - 1);
  for (unsigned j = 0; j < segments; ++j) faces.push_back({0, at(1, j + 1), at(1, j)});
  for (unsigned i = 1; i + 1 < rings; ++i)
    for (unsigned j = 0; j < segments; ++j) faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
  for (unsigned j = 0; j < segments; ++j) faces.push_back({south, at(rings - 1, j), at(rings - 1, j + 1)});
  return make_mesh(vertices, faces, "uv-sphere");
}

// A small scene with occlusion in every direction: two boxes and a sphere-ish blob.
inline Mesh scene_mesh() {
  return boxes_mesh({{{-1, -0.2f, -0.3f}, {-0.2f, 0.9f, 0.4f}}, {{0.1f, -1, -0.6f}, {0.8f, -0.1f, 0.7f}}, {{-0.5f, -0.9f, 0.5f}, {0.3f, -0.4f, 0.9f}}},
                    "three boxes");
}

// A unit sphere resting 0.01 above a thin 16-wide plate, each with its CSM (1024 maps of 64²), and
// both meshes as one (the ray casters' occluder): a receiver that is one of the occluders.
struct BallOnPlate {
  Mesh ball, plate, both;
  Csm ball_csm, plate_csm;
};
inline const BallOnPlate& ball_on_plate() {
  static const BallOnPlate built = [] {
    BallOnPlate b;
    b.ball = splatcl::testing::moved_mesh(sphere_mesh(16, 32), [](Vec3 p) { return p + Vec3{0, 1.01f, 0}; }, "ball");
    b.plate = boxes_mesh({{{-8, -0.005f, -8}, {8, 0, 8}}}, "plate");
    BuildOptions build;
    build.maps = 1024;
    build.resolution = 64;
    b.ball_csm = build_csm(b.ball, build, &runtime()).csm;
    b.plate_csm = build_csm(b.plate, build, &runtime()).csm;
    std::vector<Vec3> vertices = b.ball.vertices;
    vertices.insert(vertices.end(), b.plate.vertices.begin(), b.plate.vertices.end());
    std::vector<std::vector<std::uint32_t>> faces = splatcl::testing::face_lists(b.ball);
    for (std::vector<std::uint32_t> face : splatcl::testing::face_lists(b.plate)) {
      for (std::uint32_t& v : face) v += static_cast<std::uint32_t>(b.ball.vertices.size());
      faces.push_back(face);
    }
    b.both = make_mesh(vertices, faces, "ball on plate");
    return b;
  }();
  return built;
}

}  // namespace splatcl::csm::testing
