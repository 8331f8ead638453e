// Mesh loading, sampling and the kNN graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <random>

#include "runtime/error.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

std::string temp_file(const std::string& name, const std::string& contents) {
  const auto path = std::filesystem::temp_directory_path() / ("splatcl-splats-" + name);
  std::ofstream(path) << contents;
  return path.string();
}

void expect_error_naming(const std::function<void()>& action, const std::string& text) {
  try {
    action();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
  }
}

TEST(MeshLoad, BunnyDropsUnusedScanVertices) {
  const std::string path = model_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "shared models not found at " << SPLATCL_MODELS_DIR;
  const Mesh mesh = load_mesh(path);
  EXPECT_EQ(mesh.vertices.size(), 34834u);  // 35,947 in the file, 1,113 used by no face
  EXPECT_EQ(mesh.face_count(), 69451u);
  EXPECT_NEAR(mesh.bounds().diagonal(), 0.2502, 1e-3);
  for (const Vec3& n : mesh.normals) ASSERT_NEAR(length(n), 1.0f, 1e-4);
}

TEST(MeshLoad, ReadsOffAndPlyAndStl) {
  const std::string off = temp_file("quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  const Mesh mesh = load_mesh(off);
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_NEAR(std::fabs(mesh.normals[0].z), 1.0f, 1e-6);
  const std::string ply = temp_file("tri.ply",
                                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(load_mesh(ply).face_count(), 1u);
  const std::string stl = temp_file("tri.stl",
                                    "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  EXPECT_EQ(load_mesh(stl).face_count(), 1u);
}

TEST(MeshLoad, BadFilesGiveOneLineNamingTheFile) {
  expect_error_naming([] { load_mesh("/no/such/model.obj"); }, "/no/such/model.obj");
  const std::string garbage = temp_file("garbage.obj", "this is not a mesh\n");
  expect_error_naming([&] { load_mesh(garbage); }, garbage);
  const std::string unknown = temp_file("mesh.xyz", "1 2 3\n");
  expect_error_naming([&] { load_mesh(unknown); }, unknown);
  const std::string nan = temp_file("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  expect_error_naming([&] { load_mesh(nan); }, nan);
  const std::string empty = temp_file("points.obj", "v 0 0 0\nv 1 0 0\n");
  expect_error_naming([&] { load_mesh(empty); }, "no faces");
  expect_error_naming([] { make_mesh({{0, 0, 0}}, {{0, 1, 2}}, "broken"); }, "broken");
}

TEST(Sampling, VerticesAndDuplicates) {
  // Two triangles whose shared corners are duplicated vertices: duplicates are dropped.
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {3, 4, 5}}, "dups");
  const Samples samples = sample_mesh(mesh, SamplingOptions{}, ColorSource{});
  EXPECT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples.duplicates_dropped, 2u);
  EXPECT_EQ(samples.vertex_samples, 4u);
  EXPECT_TRUE(samples.colors[0] == (Rgba8{128, 128, 128, 255}));
}

TEST(Sampling, FaceGridSpacingAndCount) {
  // Unit square in one quad, n = 4: d = 1/4, a 5×5 grid with the boundary kept; the corners are
  // the vertices, so 25 samples in all.
  const Mesh square = plane_mesh(1);
  const Samples samples = sample_mesh(square, parse_sampling("grid:4"), ColorSource{});
  EXPECT_DOUBLE_EQ(samples.grid_spacing, 0.25);
  EXPECT_EQ(samples.size(), 25u);
  EXPECT_EQ(samples.duplicates_dropped, 4u);
  for (const Vec4& n : samples.normals) EXPECT_NEAR(std::fabs(n.z), 1.0f, 1e-6);
  // n = 0.3 (the thesis's textured bunny): spacing larger than the edge, the corners only.
  EXPECT_EQ(sample_mesh(square, parse_sampling("grid:0.3"), ColorSource{}).size(), 4u);
  EXPECT_THROW(sample_mesh(plane_mesh(1, 1000.0f), SamplingOptions{SampleMode::FaceGrid, 1e6, 1000}, ColorSource{}), Error);
}

TEST(Sampling, DegenerateFacesAddNoGridSamples) {
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {1, 0, 3}}, "degenerate");
  const Samples samples = sample_mesh(mesh, parse_sampling("grid:2"), ColorSource{});
  EXPECT_EQ(samples.size(), 7u);  // 4 vertices + (0.5, 0), (0, 0.5), (0.5, 0.5) of the right triangle
  for (const Vec4& p : samples.positions) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
}

TEST(Sampling, ParseErrors) {
  for (const char* bad : {"grid", "grid:", "grid:0", "grid:-1", "grid:x", "faces"}) EXPECT_THROW(parse_sampling(bad), Error) << bad;
  EXPECT_THROW(parse_color_field("plaid"), Error);
}

TEST(Sampling, ColorFields) {
  ColorSource soft;
  soft.field = ColorField::Soft;
  soft.bounds.add({0, 0, 0});
  soft.bounds.add({2, 1, 1});
  EXPECT_TRUE(soft.at({0, 0, 0}, nullptr) == (Rgba8{255, 0, 0, 255}));
  EXPECT_TRUE(soft.at({2, 0, 0}, nullptr) == (Rgba8{255, 255, 255, 255}));
  ColorSource hard = soft;
  hard.field = ColorField::Hard;
  // Constant inside a cell, different across some cell boundary.
  EXPECT_TRUE(hard.at({0.01f, 0.01f, 0.01f}, nullptr) == hard.at({0.02f, 0.02f, 0.02f}, nullptr));
  bool changes = false;
  for (float x = 0; x < 2; x += 0.05f) changes |= !(hard.at({x, 0.01f, 0.01f}, nullptr) == hard.at({0.01f, 0.01f, 0.01f}, nullptr));
  EXPECT_TRUE(changes);
}

TEST(Neighbors, ExactAgainstBruteForceWithIndexTies) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coordinate(0, 6);  // a small lattice: many equal distances
  std::vector<Vec4> points(400);
  for (auto& p : points) p = {static_cast<float>(coordinate(rng)), static_cast<float>(coordinate(rng)), static_cast<float>(coordinate(rng)), 0};
  // Duplicates are dropped before kNN in the pipeline; keep this set duplicate-free.
  std::sort(points.begin(), points.end(), [](const Vec4& a, const Vec4& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); });
  points.erase(std::unique(points.begin(), points.end(), [](const Vec4& a, const Vec4& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }),
               points.end());
  const unsigned k = 10;
  const Neighborhoods nb = find_neighbors(points, k);
  ASSERT_EQ(nb.k, k);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::pair<float, std::uint32_t>> all;
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (j == i) continue;
      const Vec3 d = xyz(points[j]) - xyz(points[i]);
      all.emplace_back(dot(d, d), static_cast<std::uint32_t>(j));
    }
    std::sort(all.begin(), all.end());
    // The k-th distance is exact; the set may differ only among points tied at the k-th distance.
    ASSERT_FLOAT_EQ(nb.kth_distance[i], std::sqrt(all[k - 1].first));
    for (unsigned r = 0; r < k; ++r) {
      const Vec3 d = xyz(points[nb.row(i)[r]]) - xyz(points[i]);
      ASSERT_FLOAT_EQ(dot(d, d), all[r].first) << "sample " << i << " rank " << r;
      ASSERT_NE(nb.row(i)[r], i);
    }
    EXPECT_DOUBLE_EQ(nb.weight[i], std::numbers::pi * nb.kth_distance[i] * nb.kth_distance[i]);
  }
}

TEST(Neighbors, FewerSamplesThanK) {
  const std::vector<Vec4> three{{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 2, 0, 0}};
  const Neighborhoods nb = find_neighbors(three, 10);
  EXPECT_EQ(nb.k, 2u);
  EXPECT_EQ(nb.row(0)[0], 1u);
  EXPECT_FLOAT_EQ(nb.kth_distance[0], 2.0f);
  EXPECT_EQ(find_neighbors({{0, 0, 0, 0}}, 10).k, 0u);
  EXPECT_THROW(find_neighbors(three, 0), Error);
}

}  // namespace
}  // namespace splatcl::splats
