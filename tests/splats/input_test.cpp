// Mesh loading, sampling and the kNN graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <random>

#include "io/image.hpp"
#include "runtime/error.hpp"
#include "splats/fit.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

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
  if (path.empty()) GTEST_SKIP() << "test models not found in " << SPLATCL_MODELS_DIR;
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

// Text files that start with a UTF-8 byte-order mark, and ASCII STL in upper case, read as without.
// Before, an OBJ's mark made its first vertex line unreadable, so every later index pointed one
// vertex off (a tangle of wrong triangles, self-check passing against it); OFF and PLY were
// refused, and "SOLID ... FACET" was taken for a binary STL.
TEST(MeshLoad, ByteOrderMarksAndUpperCaseStlReadAsPlainFiles) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 2 5\n";
  const Mesh plain = load_mesh(temp_file("plain.obj", obj));
  const Mesh marked = load_mesh(temp_file("bom.obj", bom + obj));
  ASSERT_EQ(marked.face_count(), plain.face_count());
  EXPECT_EQ(marked.vertices, plain.vertices);
  EXPECT_EQ(marked.corners, plain.corners);
  EXPECT_EQ(load_mesh(temp_file("bom.off", bom + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).face_count(), 1u);
  EXPECT_EQ(load_mesh(temp_file("bom.ply", bom + "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
                .face_count(),
            1u);
  const std::string stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                          "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  std::string upper = stl;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  EXPECT_EQ(load_mesh(temp_file("bom.stl", bom + stl)).face_count(), 2u);
  const Mesh shouted = load_mesh(temp_file("upper.stl", upper));
  EXPECT_EQ(shouted.face_count(), 2u);
  EXPECT_EQ(shouted.vertices.size(), 4u);
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
  // Unit square in one quad, n = 4: d = 1/4; the grid starts at the square's corner, and of its
  // 5×5 points the 3×3 strictly inside are kept (the 16 on the boundary belong to the edges and
  // vertices): 4 vertices + 9.
  const Mesh square = plane_mesh(1);
  const Samples samples = sample_mesh(square, parse_sampling("grid:4"), ColorSource{});
  EXPECT_DOUBLE_EQ(samples.grid_spacing, 0.25);
  EXPECT_EQ(samples.size(), 13u);
  EXPECT_EQ(samples.vertex_samples, 4u);
  EXPECT_EQ(samples.duplicates_dropped, 0u);
  for (std::size_t i = samples.vertex_samples; i < samples.size(); ++i) {
    const Vec4& p = samples.positions[i];
    EXPECT_TRUE(p.x == 0.25f || p.x == 0.5f || p.x == 0.75f) << p.x;
    EXPECT_TRUE(p.y == 0.25f || p.y == 0.5f || p.y == 0.75f) << p.y;
  }
  for (const Vec4& n : samples.normals) EXPECT_NEAR(std::fabs(n.z), 1.0f, 1e-6);
  // n = 0.3 (the thesis's textured bunny): spacing larger than the edge, the corners only.
  EXPECT_EQ(sample_mesh(square, parse_sampling("grid:0.3"), ColorSource{}).size(), 4u);
  EXPECT_THROW(sample_mesh(plane_mesh(1, 1000.0f), SamplingOptions{SampleMode::FaceGrid, 1e6, 0, 1000}, ColorSource{}), Error);
}

// Distance of p from the boundary of face f, positive inside (in the face's plane), and its
// distance from the face's plane.
std::pair<double, double> inside_distance(const Mesh& mesh, std::size_t f, Vec3 p) {
  const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
  const Vec3 a = mesh.vertices[mesh.corners[begin]];
  Vec3 normal{};
  for (std::uint32_t c = begin + 1; c + 1 < end; ++c)
    normal = normal + cross(mesh.vertices[mesh.corners[c]] - a, mesh.vertices[mesh.corners[c + 1]] - a);
  normal = normalized(normal);
  double inside = INFINITY;
  for (std::uint32_t c = begin; c < end; ++c) {
    const Vec3 from = mesh.vertices[mesh.corners[c]], to = mesh.vertices[mesh.corners[c + 1 == end ? begin : c + 1]];
    const Vec3 edge = normalized(to - from);
    inside = std::min(inside, static_cast<double>(dot(cross(normal, edge), p - from)));
  }
  return {inside, std::fabs(static_cast<double>(dot(normal, p - a)))};
}

// Every face sample lies strictly inside a face (not on an edge or a vertex) and in its plane; no
// two samples share a position, so shared edges and vertices are not sampled twice.
void expect_face_samples_strictly_inside(const Mesh& mesh, const Samples& samples, double plane_tolerance) {
  EXPECT_EQ(samples.duplicates_dropped, 0u);
  EXPECT_EQ(samples.vertex_samples, mesh.vertices.size());
  std::vector<std::tuple<float, float, float>> positions;
  for (const Vec4& p : samples.positions) positions.emplace_back(p.x, p.y, p.z);
  std::sort(positions.begin(), positions.end());
  EXPECT_EQ(std::adjacent_find(positions.begin(), positions.end()), positions.end()) << "duplicate sample";
  for (std::size_t i = samples.vertex_samples; i < samples.size(); ++i) {
    const Vec3 p = xyz(samples.positions[i]);
    double best = -INFINITY;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const auto [inside, off_plane] = inside_distance(mesh, f, p);
      if (off_plane <= plane_tolerance) best = std::max(best, inside);
    }
    ASSERT_GT(best, 0.0) << "face sample " << i << " is not strictly inside a face";
    for (const Vec3& v : mesh.vertices) ASSERT_GT(length(v - p), 0.0f) << "face sample " << i << " sits on a vertex";
  }
}

TEST(Sampling, FaceGridSamplesLieStrictlyInsideTheirFaces) {
  // Two triangles sharing a diagonal: the first's grid runs along the x axis and crosses the
  // diagonal at grid points, the second's runs along the diagonal itself; neither keeps a point on it.
  const Mesh split = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}, "split square");
  const Samples samples = sample_mesh(split, parse_sampling("grid:4"), ColorSource{});
  expect_face_samples_strictly_inside(split, samples, 1e-6);
  for (std::size_t i = samples.vertex_samples; i < samples.size(); ++i)
    EXPECT_GT(std::fabs(samples.positions[i].x - samples.positions[i].y), 1e-6f) << "sample " << i << " on the shared diagonal";
  EXPECT_GT(samples.size(), samples.vertex_samples);
  // Curved, quads and triangles; the cube's grid lines meet its edges at grid points.
  const Mesh sphere = sphere_mesh(12, 16);
  expect_face_samples_strictly_inside(sphere, sample_mesh(sphere, parse_sampling("grid:3"), ColorSource{}), 1e-5);
  const Mesh cube = cube_mesh();
  const Samples cube_samples = sample_mesh(cube, parse_sampling("grid:8"), ColorSource{});
  expect_face_samples_strictly_inside(cube, cube_samples, 1e-6);
  EXPECT_EQ(cube_samples.size(), 8u + 6u * 7u * 7u);
}

TEST(Sampling, BunnyFaceGridMatchesTheThesisCount) {
  const std::string path = model_path("stanford-bunny.obj");
  if (path.empty()) GTEST_SKIP() << "test models not found in " << SPLATCL_MODELS_DIR;
  // Thesis §3.3: n = 0.3 on the bunny gives 110,174 samples (from 34,801 vertices). Ours: 34,834
  // vertices + 75,637 face samples, no duplicate dropped.
  const Samples samples = sample_mesh(load_mesh(path), parse_sampling("grid:0.3"), ColorSource{});
  EXPECT_EQ(samples.vertex_samples, 34834u);
  EXPECT_EQ(samples.duplicates_dropped, 0u);
  EXPECT_EQ(samples.size(), 110471u);
  EXPECT_NEAR(static_cast<double>(samples.size()) / 110174.0, 1.0, 0.005);
}

TEST(Sampling, DegenerateFacesAddNoGridSamples) {
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {1, 0, 3}}, "degenerate");
  // d = 1/4: 4 vertices + (1/4, 1/4), (1/2, 1/4), (1/4, 1/2), the grid points strictly inside the
  // right triangle; the collinear face adds nothing.
  const Samples samples = sample_mesh(mesh, parse_sampling("grid:4"), ColorSource{});
  EXPECT_EQ(samples.size(), 7u);
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

// The rainbow field: deterministic, fully saturated colours (min channel 0, max channel 255 or 128),
// every hue sector present, continuous inside a cell, a jump of ≥ 127 across every cell face.
TEST(Sampling, RainbowFieldContinuousInCellsHardAcrossFaces) {
  EXPECT_EQ(parse_color_field("rainbow"), ColorField::Rainbow);
  EXPECT_STREQ(to_string(ColorField::Rainbow), "rainbow");
  ColorSource rainbow;
  rainbow.field = ColorField::Rainbow;
  rainbow.bounds.add({0, 0, 0});
  rainbow.bounds.add({2, 1, 1});
  const float cell = rainbow.bounds.diagonal() / 8.0f;
  const auto channels = [](Rgba8 c) { return std::array<int, 3>{c.r, c.g, c.b}; };
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::array<bool, 6> sectors{};
  for (int trial = 0; trial < 2000; ++trial) {
    // A point well inside a random cell, and a step of cell / 1000 that stays inside it.
    const Vec3 cell_index{std::floor(unit(rng) * 12), std::floor(unit(rng) * 6), std::floor(unit(rng) * 6)};
    const auto inside = [&] { return 0.1f + 0.8f * unit(rng); };
    const Vec3 p{(cell_index.x + inside()) * cell, (cell_index.y + inside()) * cell, (cell_index.z + inside()) * cell};
    const Vec3 q{p.x + cell / 1000, p.y - cell / 2000, p.z + cell / 1500};
    const Rgba8 a = rainbow.at(p, nullptr), b = rainbow.at(q, nullptr);
    ASSERT_TRUE(a == rainbow.at(p, nullptr)) << "deterministic";
    const auto ca = channels(a), cb = channels(b);
    const int hi = *std::max_element(ca.begin(), ca.end()), lo = *std::min_element(ca.begin(), ca.end());
    EXPECT_EQ(lo, 0);
    EXPECT_TRUE(hi == 255 || hi == 128) << hi;
    EXPECT_EQ(a.a, 255);
    // Slope ≤ 6 · 255 levels per hue cycle · 4 cycles per cell; the step is ≤ 1.3 / 1000 cell; + 1 rounding.
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(ca[c] - cb[c]), 9) << "continuous inside a cell";
    const int top = static_cast<int>(std::max_element(ca.begin(), ca.end()) - ca.begin());
    sectors[static_cast<std::size_t>(2 * top + (ca[(top + 1) % 3] > ca[(top + 2) % 3] ? 0 : 1))] = true;
    // Across the cell's x face (and so every face, by symmetry of the parity rule) the brightness jumps.
    const float face = (cell_index.x + 1) * cell;
    const auto cx = channels(rainbow.at({face - cell / 1e4f, p.y, p.z}, nullptr)),
               cy = channels(rainbow.at({face + cell / 1e4f, p.y, p.z}, nullptr));
    EXPECT_GE(std::abs(*std::max_element(cx.begin(), cx.end()) - *std::max_element(cy.begin(), cy.end())), 127)
        << "hard edge across the face";
  }
  for (std::size_t s = 0; s < sectors.size(); ++s) EXPECT_TRUE(sectors[s]) << "hue sector " << s;
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

// Two sheets 0.05 apart on a 0.2 lattice (a thin plate's sides, normals +z and -z): with the
// normals, every row holds the k nearest of the sample's own sheet, exactly (brute force), where
// the plain graph takes the sheet below first; a row on a sheet of fewer than k + 1 samples is
// filled with the other sheet's nearest. At crease 180 (cosine -2) the plain graph.
TEST(Neighbors, PassOverTheOtherSheetOfAThinPlate) {
  std::vector<Vec4> points, normals;
  for (int sheet = 0; sheet < 2; ++sheet)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        points.push_back({0.2f * static_cast<float>(x), 0.2f * static_cast<float>(y), sheet ? 0.0f : 0.05f, 0});
        normals.push_back({0, 0, sheet ? -1.0f : 1.0f, 0});
      }
  const std::size_t one_sheet = points.size() / 2;
  const float crease_cos = crease_cosine(60.0f);
  const unsigned k = 10;
  const Neighborhoods plain = find_neighbors(points, k);
  const Neighborhoods sheets = find_neighbors(points, k, &normals, crease_cos);
  std::size_t plain_crossings = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::pair<float, std::uint32_t>> same;
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (j == i || (j < one_sheet) != (i < one_sheet)) continue;
      const Vec3 d = xyz(points[j]) - xyz(points[i]);
      same.emplace_back(dot(d, d), static_cast<std::uint32_t>(j));
    }
    std::sort(same.begin(), same.end());
    for (unsigned r = 0; r < k; ++r) {
      ASSERT_EQ(sheets.row(i)[r], same[r].second) << "sample " << i << " rank " << r;
      plain_crossings += (plain.row(i)[r] < one_sheet) != (i < one_sheet);
    }
    ASSERT_FLOAT_EQ(sheets.kth_distance[i], std::sqrt(same[k - 1].first));
  }
  EXPECT_GE(plain_crossings, points.size()) << "the plain graph should reach the other sheet";
  const Neighborhoods thesis = find_neighbors(points, k, &normals, crease_cosine(180.0f));
  EXPECT_EQ(thesis.indices, plain.indices);

  // A sheet of 3 samples above 20: each row takes its 2 others, then the nearest 8 below.
  const std::vector<Vec4> small{{0, 0, 0.05f, 0}, {0.2f, 0, 0.05f, 0}, {0, 0.2f, 0.05f, 0}};
  std::vector<Vec4> mixed(small), mixed_normals(3, Vec4{0, 0, 1, 0});
  for (int x = 0; x < 20; ++x) mixed.push_back({0.1f * static_cast<float>(x), 0, 0, 0}), mixed_normals.push_back({0, 0, -1, 0});
  const Neighborhoods filled = find_neighbors(mixed, k, &mixed_normals, crease_cos);
  EXPECT_EQ(filled.row(0)[0], 1u);
  EXPECT_EQ(filled.row(0)[1], 2u);
  for (unsigned r = 2; r < k; ++r) EXPECT_GE(filled.row(0)[r], 3u);
  EXPECT_THROW(find_neighbors(mixed, k, &normals, crease_cos), Error);  // one normal per position

  // An undefined (zero) normal takes no side: at a crease angle over 90 degrees it was opposed to
  // every sample, so its neighbours on the sheet left it out of their rows.
  std::vector<Vec4> zero_normals = normals;
  zero_normals[0] = {0, 0, 0, 0};
  const Neighborhoods wide = find_neighbors(points, k, &zero_normals, crease_cosine(120.0f));
  const std::uint32_t* next_row = wide.row(1);  // sample 1 lies 0.2 from sample 0 on the same sheet
  EXPECT_NE(std::find(next_row, next_row + k, 0u), next_row + k);
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

// The nearest texel of texture coordinates on and beyond the unit square's edges: 1 is the last
// texel's edge (it gave the first texel's colour), outside [0, 1] the texture repeats.
TEST(Sampling, TextureCoordinatesOfOneTakeTheLastTexel) {
  ColorSource colors;
  colors.texture = Texture{2, 2, {10, 0, 0, 20, 0, 0, 30, 0, 0, 40, 0, 0}};  // rows top down: 10 20 / 30 40
  const auto red_at = [&](float u, float v) {
    const float uv[2] = {u, v};
    return colors.at({}, uv).r;
  };
  EXPECT_EQ(red_at(0.0f, 0.0f), 30);  // v runs upwards: the bottom row
  EXPECT_EQ(red_at(1.0f, 0.0f), 40);
  EXPECT_EQ(red_at(0.0f, 1.0f), 10);
  EXPECT_EQ(red_at(1.0f, 1.0f), 20);
  EXPECT_EQ(red_at(0.999f, 0.5001f), 20);
  EXPECT_EQ(red_at(1.25f, 0.25f), 30);   // repeated
  EXPECT_EQ(red_at(-0.25f, -0.25f), 20);
}

// The textured colour variant end to end: an OBJ with texture coordinates and a PNG read through
// OpenImageIO. A 2x2 texture (v upwards: red, green below; blue, white above) is mapped affinely
// onto the unit square with a 0.1 margin, so every sample's colour is the texel of its quadrant.
TEST(Sampling, TextureColoursFollowTheTexcoordsOfVerticesAndGridSamples) {
  const auto texture_path = (std::filesystem::temp_directory_path() / "splatcl-splats-quad-texture.png").string();
  write_image_rgb(texture_path, 2, 2, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
  const std::string obj = temp_file("textured-quad.obj",
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                    "vt 0.1 0.1\nvt 0.9 0.1\nvt 0.9 0.9\nvt 0.1 0.9\n"
                                    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
  const Mesh mesh = load_mesh(obj);
  ASSERT_TRUE(mesh.has_texcoords());
  ColorSource colors;
  colors.texture = load_texture(texture_path);
  ASSERT_EQ(colors.texture->width, 2);
  for (const char* sampling : {"vertices", "grid:8"}) {
    const Samples samples = sample_mesh(mesh, parse_sampling(sampling), colors);
    ASSERT_GE(samples.size(), 4u) << sampling;
    std::size_t checked = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Vec4 p = samples.positions[i];
      if (std::fabs(p.x - 0.5f) < 1e-3f || std::fabs(p.y - 0.5f) < 1e-3f) continue;  // on a texel edge
      const bool right = p.x > 0.5f, top = p.y > 0.5f;
      const Rgba8 expected = top ? (right ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 255, 255})
                                 : (right ? Rgba8{0, 255, 0, 255} : Rgba8{255, 0, 0, 255});
      const Rgba8 got = samples.colors[i];
      EXPECT_TRUE(got.r == expected.r && got.g == expected.g && got.b == expected.b && got.a == 255)
          << sampling << " sample " << i << " at (" << p.x << ", " << p.y << ")";
      ++checked;
    }
    EXPECT_GE(checked, 4u) << sampling;
  }
  expect_error_naming([] { load_texture("/nonexistent/splatcl-texture.png"); }, "/nonexistent/splatcl-texture.png");
}

}  // namespace
}  // namespace splatcl::splats
