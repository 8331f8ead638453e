// The surface the splats are checked against: exact point-to-triangle distances and the box tree
// against brute force, and area-uniform points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "splats/surface.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

// Distance from p to triangle t by brute force: the plane projection when it falls inside, else
// the nearest of the three edges sampled densely and their exact segment distances.
double brute_distance(const SurfaceTriangle& t, DVec3 p) {
  const auto segment = [&](DVec3 a, DVec3 b) {
    const DVec3 ab = b - a;
    const double s = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
    return length(a + s * ab - p);
  };
  double best = std::min({segment(t.a, t.b), segment(t.b, t.c), segment(t.c, t.a)});
  const DVec3 n = t.normal;
  const DVec3 q = p - dot(p - t.a, n) * n;
  const auto side = [&](DVec3 a, DVec3 b) { return dot(cross(b - a, q - a), n); };
  if (side(t.a, t.b) >= 0 && side(t.b, t.c) >= 0 && side(t.c, t.a) >= 0) best = std::min(best, std::fabs(dot(p - t.a, n)));
  return best;
}

// `count` boxes of the given size at uniform random corners in the unit cube.
std::vector<BoxTree::Box> random_boxes(std::size_t count, std::uint64_t seed, DVec3 size) {
  std::vector<BoxTree::Box> boxes(count);
  SplitMix64 random{seed};
  for (auto& box : boxes) {
    const DVec3 c{random.uniform(), random.uniform(), random.uniform()};
    box.add(c), box.add(c + size);
  }
  return boxes;
}

TEST(Surface, ClosestPointMatchesBruteForce) {
  SplitMix64 random{7};
  const auto coordinate = [&] { return 2.0 * random.uniform() - 1.0; };
  for (int trial = 0; trial < 2000; ++trial) {
    const Mesh mesh = make_mesh({{static_cast<float>(coordinate()), static_cast<float>(coordinate()), static_cast<float>(coordinate())},
                                 {static_cast<float>(coordinate()), static_cast<float>(coordinate()), static_cast<float>(coordinate())},
                                 {static_cast<float>(coordinate()), static_cast<float>(coordinate()), static_cast<float>(coordinate())}},
                                {{0, 1, 2}}, "triangle");
    const auto triangles = surface_triangles(mesh);
    ASSERT_EQ(triangles.size(), 1u);
    const DVec3 p{3 * coordinate(), 3 * coordinate(), 3 * coordinate()};
    EXPECT_NEAR(length(closest_point(triangles[0], p) - p), brute_distance(triangles[0], p), 1e-9) << trial;
  }
}

// A sphere, and meshes whose triangles the tree indexes in pieces: a fan of needles (each cut into
// slices across its length) and a stack of obtuse caps (each split at its longest edge). Points
// throughout the box and close to the flat meshes' plane, where the pieces' boxes must hold every
// point of their triangle.
TEST(Surface, NearestAndWithinMatchBruteForceOverAMesh) {
  std::vector<std::vector<std::uint32_t>> cap_faces;
  std::vector<Vec3> cap_vertices;
  for (std::uint32_t k = 0; k < 30; ++k) {  // caps 1 long and 0.01 high, stacked 0.04 apart
    const float y = -0.6f + 0.04f * static_cast<float>(k);
    cap_vertices.insert(cap_vertices.end(), {{-0.5f + 0.01f * static_cast<float>(k), y, 0.0f}, {0.5f, y, 0.0f}, {0.0f, y + 0.01f, 0.0f}});
    cap_faces.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  const Mesh meshes[] = {testing::sphere_mesh(12, 24), testing::sliver_fan_mesh(300), make_mesh(cap_vertices, cap_faces, "caps")};
  for (const Mesh& mesh : meshes) {
    SCOPED_TRACE(mesh.source);
    const Surface surface(mesh);
    ASSERT_GE(surface.triangles().size(), 30u);
    SplitMix64 random{11};
    for (int trial = 0; trial < 1000; ++trial) {
      const double z = trial % 2 ? 2.4 * random.uniform() - 1.2 : 0.02 * (random.uniform() - 0.5);
      const DVec3 p{2.4 * random.uniform() - 1.2, 2.4 * random.uniform() - 1.2, z};
      double best = INFINITY;
      for (const SurfaceTriangle& t : surface.triangles()) best = std::min(best, brute_distance(t, p));
      const Surface::Nearest nearest = surface.nearest(p);
      EXPECT_NEAR(nearest.distance, best, 1e-9);
      ASSERT_LT(nearest.triangle, surface.triangles().size());
      EXPECT_NEAR(length(closest_point(surface.triangles()[nearest.triangle], p) - p), best, 1e-9);
      EXPECT_TRUE(surface.within(p, best + 1e-9));
      EXPECT_FALSE(surface.within(p, best * 0.999 - 1e-12));
      EXPECT_EQ(surface.nearest(p, best * 0.999 - 1e-12).triangle, UINT32_MAX);
    }
  }
}

TEST(Surface, RecentAnswersOnlySpeedQueriesUp) {
  // Walks of nearby points (as the splat checks make them) with jumps between walks: with a Recent
  // the answers are those without one, for within and for nearest (the same triangle on ties).
  const Mesh mesh = testing::sphere_mesh(24, 48);
  const Surface surface(mesh);
  SplitMix64 random{5};
  Surface::Recent recent;
  DVec3 p{0, 0, 1};
  std::size_t inside = 0, outside = 0;
  for (int step = 0; step < 4000; ++step) {
    if (step % 200 == 0) recent = {};
    const double jump = step % 50 == 0 ? 1.0 : 0.02;
    p = p + DVec3{jump * (random.uniform() - 0.5), jump * (random.uniform() - 0.5), jump * (random.uniform() - 0.5)};
    p = (0.9 + 0.2 * random.uniform()) * normalized(p);
    const double radius = 0.03 * random.uniform();
    const bool plain = surface.within(p, radius);
    ASSERT_EQ(surface.within(p, radius, &recent), plain) << step;
    (plain ? inside : outside) += 1;
    const double limit = step % 3 == 0 ? INFINITY : 0.05;
    const Surface::Nearest expected = surface.nearest(p, limit), got = surface.nearest(p, limit, &recent);
    ASSERT_EQ(got.triangle, expected.triangle) << step;
    ASSERT_EQ(got.distance, expected.distance) << step;
  }
  EXPECT_GT(inside, 500u);
  EXPECT_GT(outside, 500u);
}

TEST(Surface, TreeRegionsHoldTheirItems) {
  // ancestor(item, k) is a node whose subtree visit reaches the item; k = 0 is its leaf and a
  // large k the root (the whole tree).
  const std::vector<BoxTree::Box> boxes = random_boxes(1000, 9, {0.01, 0.01, 0.01});
  const BoxTree tree(boxes);
  EXPECT_EQ(tree.ancestor(17, 100), 0u);
  for (std::uint32_t item = 0; item < boxes.size(); item += 37)
    for (const int levels : {0, 1, 3, 6}) {
      const DVec3 p = 0.5 * (boxes[item].lo + boxes[item].hi);
      bool reached = false;
      double radius = 0;
      tree.visit(p, radius, [&](std::uint32_t j, double&) { return reached = j == item; }, tree.ancestor(item, levels));
      EXPECT_TRUE(reached) << item << " " << levels;
    }
}

TEST(Surface, OutwardVisitReachesEveryItemOnceFromAnyStart) {
  const std::vector<BoxTree::Box> boxes = random_boxes(500, 13, {0.02, 0.01, 0.03});
  const BoxTree tree(boxes);
  for (std::uint32_t item = 0; item < boxes.size(); item += 23)
    for (const int levels : {0, 2, 5, 100}) {
      std::vector<int> seen(boxes.size(), 0);
      double radius = INFINITY;
      tree.visit_outward({0.5, 0.5, 0.5}, radius, [&](std::uint32_t j, double&) { return ++seen[j], false; }, tree.ancestor(item, levels));
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(boxes.size())) << item << " " << levels;
    }
}

TEST(Surface, RecentWalksMatchBruteForceOnSliversAndMixedSizes) {
  // A soup of triangles from 1e-4 to 1 across, a third of them slivers (a corner near the midpoint
  // of the opposite edge), so the corner-ball and plane rejections and the outward walk meet both
  // needle-shaped and tiny triangles: every answer is the brute-force one.
  SplitMix64 random{17};
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::uint32_t f = 0; f < 600; ++f) {
    const double size = std::pow(10.0, -4 * random.uniform());
    const DVec3 c{random.uniform(), random.uniform(), 0.2 * random.uniform()};
    const auto corner = [&] { return c + size * DVec3{random.uniform() - 0.5, random.uniform() - 0.5, random.uniform() - 0.5}; };
    const DVec3 a = corner(), b = corner();
    const DVec3 d = f % 3 == 0 ? 0.5 * (a + b) + 1e-3 * size * DVec3{random.uniform(), random.uniform(), random.uniform()} : corner();
    for (const DVec3 v : {a, b, d}) vertices.push_back(to_float(v));
    faces.push_back({3 * f, 3 * f + 1, 3 * f + 2});
  }
  const Surface surface(make_mesh(vertices, faces, "soup"));
  // The tiniest slivers (offsets of 1e-11 at coordinates near 1) are zero-area to float rounding:
  // no surface triangle (Mesh::zero_area_face).
  ASSERT_GT(surface.triangles().size(), 520u);
  Surface::Recent recent;
  DVec3 p{0.5, 0.5, 0.1};
  for (int step = 0; step < 3000; ++step) {
    const double jump = step % 40 == 0 ? 0.5 : 0.01;
    p = p + DVec3{jump * (random.uniform() - 0.5), jump * (random.uniform() - 0.5), jump * (random.uniform() - 0.5)};
    double best = INFINITY;
    for (const SurfaceTriangle& t : surface.triangles()) best = std::min(best, brute_distance(t, p));
    const Surface::Nearest nearest = surface.nearest(p, INFINITY, &recent);
    ASSERT_NEAR(nearest.distance, best, 1e-9) << step;
    const double radius = best * (step % 2 == 0 ? 1.001 : 0.999) + (step % 2 == 0 ? 1e-12 : -1e-12);
    ASSERT_EQ(surface.within(p, radius, &recent), step % 2 == 0) << step;
  }
}

TEST(Surface, NonPlanarQuadIsItsTwoTriangles) {
  // A quad with one corner lifted: the surface passes through all four corners.
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0}}, {{0, 1, 2, 3}}, "bent quad");
  const Surface surface(mesh);
  ASSERT_EQ(surface.triangles().size(), 2u);
  EXPECT_NEAR(surface.nearest({1, 1, 0.5}).distance, 0.0, 1e-12);
  EXPECT_NEAR(surface.nearest({0.5, 0.5, 0.25}).distance, 0.0, 1e-7);  // on the diagonal corner 0 - corner 2
}

TEST(Surface, UniformPointsAreOnTheSurfaceSpreadByArea) {
  // Two unit squares side by side, one split into 100 small quads and one into a single quad: by
  // area each gets half of the points whatever its triangle count.
  const Mesh fine = testing::plane_mesh(10);
  std::vector<Vec3> vertices = fine.vertices;
  std::vector<std::vector<std::uint32_t>> faces = splatcl::testing::face_lists(fine);
  const std::uint32_t base = static_cast<std::uint32_t>(vertices.size());
  for (const Vec3 v : {Vec3{1.5f, 0, 0}, Vec3{2.5f, 0, 0}, Vec3{2.5f, 1, 0}, Vec3{1.5f, 1, 0}}) vertices.push_back(v);
  faces.push_back({base, base + 1, base + 2, base + 3});
  const Surface surface(make_mesh(vertices, faces, "two squares"));
  EXPECT_NEAR(surface.area(), 2.0, 1e-6);
  const auto points = surface.uniform_points(20000, 3);
  ASSERT_EQ(points.size(), 20000u);
  std::size_t right = 0;
  for (const auto& p : points) {
    EXPECT_NEAR(p.position.z, 0.0, 1e-12);
    EXPECT_NEAR(std::fabs(p.normal.z), 1.0, 1e-12);
    right += p.position.x > 1.25 ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(right) / 20000.0, 0.5, 0.02);
  const auto again = surface.uniform_points(20000, 3);
  EXPECT_EQ(again.back().position.x, points.back().position.x);  // seeded: the same points
}

TEST(BoxTree, VisitsEveryBoxWithinTheRadius) {
  SplitMix64 random{5};
  std::vector<BoxTree::Box> boxes(1000);
  for (auto& b : boxes) {
    const DVec3 c{random.uniform(), random.uniform(), random.uniform()};
    const DVec3 h{0.05 * random.uniform(), 0.05 * random.uniform(), 0.05 * random.uniform()};
    b.add(c - h), b.add(c + h);
  }
  const BoxTree tree(boxes);
  for (int trial = 0; trial < 100; ++trial) {
    const DVec3 p{random.uniform(), random.uniform(), random.uniform()};
    double radius = 0.1 * random.uniform();
    std::vector<std::uint32_t> seen;
    tree.visit(p, radius, [&](std::uint32_t item, double&) { return seen.push_back(item), false; });
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());  // each at most once
    std::size_t within = 0;
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
      if (boxes[i].distance(p) > radius) continue;
      ++within;
      EXPECT_TRUE(std::binary_search(seen.begin(), seen.end(), i)) << i;
    }
    // Whole leaves of at most 4 are visited, not the whole tree.
    EXPECT_LE(seen.size(), 8 * within + 32);
  }
  double radius = 1;
  std::size_t visits = 0;
  BoxTree{}.visit({0, 0, 0}, radius, [&](std::uint32_t, double&) { return ++visits, false; });
  EXPECT_EQ(visits, 0u);
}

}  // namespace
}  // namespace splatcl::splats
