// clip_to_surface against splats whose overhang is known analytically: past a cube's edge (a clip
// line at the edge), on a face (unchanged, unless drawn at a splat scale that takes it past the
// edge), an elongated splat tangent to a sphere (its major axis shortened to where the sphere falls
// more than the tolerance below it), and splats on a cube's corner (two clip lines, along its edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "splats/surface.hpp"
#include "splats/surface_fit.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

SplatRecord ellipse(Vec3 centre, Vec3 normal, Vec3 major, Vec3 minor) {
  SplatRecord s;
  s.center = centre, s.normal = normal, s.major = major, s.minor = minor;
  return s;
}

// Fitted as drawn at splat scale k; the second clip lines of a corner in `second`.
SurfaceClipStats clip(const Surface& surface, std::vector<SplatRecord>& splats, double tolerance, double k = 1.0,
                      std::vector<ClipLine>* second = nullptr) {
  std::vector<ClipLine> lines;
  const SurfaceClipStats stats = clip_to_surface(surface, splats, tolerance, k, lines);
  EXPECT_EQ(lines.size(), splats.size());
  if (second) *second = lines;
  return stats;
}

TEST(SurfaceClip, CutsAtASharpEdgeAndLeavesAFaceAlone) {
  const Surface cube(cube_mesh());
  const double tolerance = 0.005;
  // On the top face z = 1, radius 0.2: one 0.1 past the edge x = 1, one well inside the face.
  std::vector<SplatRecord> splats{ellipse({0.9f, 0.5f, 1.0f}, {0, 0, 1}, {0.2f, 0, 0}, {0, 0.2f, 0}),
                                  ellipse({0.5f, 0.5f, 1.0f}, {0, 0, 1}, {0.2f, 0, 0}, {0, 0.2f, 0})};
  const SurfaceClipStats stats = clip(cube, splats, tolerance);
  EXPECT_EQ(stats.clipped, 1u);
  EXPECT_EQ(stats.shortened, 0u);
  // The clip line is the edge, to the tolerance (a point in the plane d past the edge is d from the cube).
  EXPECT_NEAR(splats[0].clip_x, 1.0f, 0.01f);
  EXPECT_NEAR(splats[0].clip_y, 0.0f, 0.1f);
  EXPECT_GE(splats[0].clip_offset, 0.1f);
  EXPECT_LE(splats[0].clip_offset, 0.1f + tolerance + 0.01f);
  EXPECT_FLOAT_EQ(length(splats[0].major), 0.2f);
  EXPECT_TRUE(std::isinf(splats[1].clip_offset));
  EXPECT_FLOAT_EQ(length(splats[1].major), 0.2f);
  EXPECT_FLOAT_EQ(length(splats[1].minor), 0.2f);
  // A splat that already has a clip line is left as it is.
  std::vector<SplatRecord> clipped{splats[0]};
  clipped[0].clip_offset = 0.15f;
  EXPECT_EQ(clip(cube, clipped, tolerance).clipped, 0u);
  EXPECT_EQ(clipped[0].clip_offset, 0.15f);
}

// The fit measures a splat as drawn: 0.02 short of the edge x = 1 at k = 1, 0.03 past it at k = 1.5,
// where its clip line (in model units, which the shaders keep in place at any k) is the edge.
TEST(SurfaceClip, MeasuresTheSplatAtItsDrawnScale) {
  const Surface cube(cube_mesh());
  const double tolerance = 0.005;
  const SplatRecord splat = ellipse({0.88f, 0.5f, 1.0f}, {0, 0, 1}, {0.1f, 0, 0}, {0, 0.1f, 0});
  std::vector<SplatRecord> at_one{splat}, at_one_and_a_half{splat};
  EXPECT_EQ(clip(cube, at_one, tolerance, 1.0).clipped, 0u);
  EXPECT_TRUE(std::isinf(at_one[0].clip_offset));
  EXPECT_EQ(clip(cube, at_one_and_a_half, tolerance, 1.5).clipped, 1u);
  EXPECT_NEAR(at_one_and_a_half[0].clip_x, 1.0f, 0.01f);
  EXPECT_GE(at_one_and_a_half[0].clip_offset, 0.12f);
  EXPECT_LE(at_one_and_a_half[0].clip_offset, 0.12f + tolerance + 0.005f);
  EXPECT_FLOAT_EQ(length(at_one_and_a_half[0].major), 0.1f);
}

TEST(SurfaceClip, ShortensAnElongatedSplatOnACurvedSurface) {
  const Surface sphere(sphere_mesh(96, 192));
  // Tangent at the pole (0, 0, 1) of the unit sphere: at distance t along the plane the sphere lies
  // about t²/2 below it, so the major axis ends near sqrt(2 · tolerance).
  const double tolerance = 0.01;
  std::vector<SplatRecord> splats{ellipse({0, 0, 1}, {0, 0, 1}, {0.5f, 0, 0}, {0, 0.1f, 0})};
  const SurfaceClipStats stats = clip(sphere, splats, tolerance);
  EXPECT_EQ(stats.shortened, 1u);
  EXPECT_EQ(stats.clipped, 0u);
  EXPECT_TRUE(std::isinf(splats[0].clip_offset));
  EXPECT_NEAR(length(splats[0].major), std::sqrt(2 * tolerance), 0.02);
  EXPECT_FLOAT_EQ(length(splats[0].minor), 0.1f);
  // Shortened never below the minor axis: a wide one that still stands off the sphere all round
  // at that length is then shrunk on both axes to the same reach.
  std::vector<SplatRecord> wide{ellipse({0, 0, 1}, {0, 0, 1}, {0.5f, 0, 0}, {0, 0.3f, 0})};
  const SurfaceClipStats wide_stats = clip(sphere, wide, tolerance);
  EXPECT_EQ(wide_stats.shortened, 1u);
  EXPECT_EQ(wide_stats.shrunk, 1u);
  EXPECT_NEAR(length(wide[0].major), std::sqrt(2 * tolerance), 0.02);
  EXPECT_NEAR(length(wide[0].minor), std::sqrt(2 * tolerance), 0.02);
}

// Distance from a point of the top face's plane z = 1 to the unit cube: its distance to the square.
double off_the_top_face(double x, double y) {
  const double dx = std::max({0.0, -x, x - 1}), dy = std::max({0.0, -y, y - 1});
  return std::hypot(dx, dy);
}

// At a corner the surface keeps a quadrant of a splat's disc (or less), which no single line cuts
// out: a splat on the corner and one beside it get two clip lines, along the corner's two edges, so
// that what they keep stays within the tolerance of the cube and still covers the face up to the
// corner's tip (shrinking them instead rounds the corner off).
TEST(SurfaceClip, CutsSplatsAtAConvexCornerAlongBothEdges) {
  const Surface cube(cube_mesh());
  const double tolerance = 0.005;
  std::vector<SplatRecord> splats{ellipse({1.0f, 1.0f, 1.0f}, {0, 0, 1}, {0.08f, 0, 0}, {0, 0.08f, 0}),
                                  ellipse({0.97f, 0.97f, 1.0f}, {0, 0, 1}, {0.06f, 0.0f, 0}, {0, 0.05f, 0})};
  std::vector<ClipLine> second;
  const SurfaceClipStats stats = clip(cube, splats, tolerance, 1.0, &second);
  EXPECT_EQ(stats.clipped, 2u);
  EXPECT_EQ(stats.cornered, 2u);
  EXPECT_EQ(stats.shrunk, 0u);
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const SplatRecord& s = splats[i];
    ASSERT_TRUE(std::isfinite(s.clip_offset) && std::isfinite(second[i].offset)) << i;
    EXPECT_FLOAT_EQ(length(s.major), i == 0 ? 0.08f : 0.06f);
    // Local coordinates along the splat's axes (here x and y).
    const auto kept = [&](double x, double y) {
      const double lx = (x - s.center.x) / length(s.major), ly = (y - s.center.y) / length(s.minor);
      if (lx * lx + ly * ly > 1) return false;
      const double px = x - s.center.x, py = y - s.center.y;
      return px * s.clip_x + py * s.clip_y <= s.clip_offset && px * second[i].x + py * second[i].y <= second[i].offset;
    };
    double worst = 0;
    std::size_t face_points = 0, face_kept = 0;
    for (int gx = -100; gx <= 100; ++gx)
      for (int gy = -100; gy <= 100; ++gy) {
        const double x = s.center.x + 0.001 * gx, y = s.center.y + 0.001 * gy;
        const bool on_face = x <= 1 && y <= 1;
        const double lx = (x - s.center.x) / length(s.major), ly = (y - s.center.y) / length(s.minor);
        if (on_face && lx * lx + ly * ly <= 1) ++face_points, face_kept += kept(x, y);
        if (kept(x, y)) worst = std::max(worst, off_the_top_face(x, y));
      }
    // Everything kept lies within the tolerance (and what falls between the fit's 64 directions);
    // the face under the splat is kept to the corner's tip.
    EXPECT_LE(worst, 1.5 * tolerance) << "splat " << i;
    EXPECT_EQ(face_kept, face_points) << "splat " << i;
    EXPECT_TRUE(kept(0.999, 0.999)) << "splat " << i;
  }
}

}  // namespace
}  // namespace splatcl::splats
