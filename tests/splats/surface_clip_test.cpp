// clip_to_surface against splats whose overhang is known analytically: past a cube's edge (a clip
// line at the edge), on a face (unchanged), and an elongated splat tangent to a sphere (its major
// axis shortened to where the sphere falls more than the tolerance below it), and splats on a
// cube's corner (shrunk into it).
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

TEST(SurfaceClip, CutsAtASharpEdgeAndLeavesAFaceAlone) {
  const Surface cube(cube_mesh());
  const double tolerance = 0.005;
  // On the top face z = 1, radius 0.2: one 0.1 past the edge x = 1, one well inside the face.
  std::vector<SplatRecord> splats{ellipse({0.9f, 0.5f, 1.0f}, {0, 0, 1}, {0.2f, 0, 0}, {0, 0.2f, 0}),
                                  ellipse({0.5f, 0.5f, 1.0f}, {0, 0, 1}, {0.2f, 0, 0}, {0, 0.2f, 0})};
  const SurfaceClipStats stats = clip_to_surface(cube, splats, tolerance);
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
  EXPECT_EQ(clip_to_surface(cube, clipped, tolerance).clipped, 0u);
  EXPECT_EQ(clipped[0].clip_offset, 0.15f);
}

TEST(SurfaceClip, ShortensAnElongatedSplatOnACurvedSurface) {
  const Surface sphere(sphere_mesh(96, 192));
  // Tangent at the pole (0, 0, 1) of the unit sphere: at distance t along the plane the sphere lies
  // about t²/2 below it, so the major axis ends near sqrt(2 · tolerance).
  const double tolerance = 0.01;
  std::vector<SplatRecord> splats{ellipse({0, 0, 1}, {0, 0, 1}, {0.5f, 0, 0}, {0, 0.1f, 0})};
  const SurfaceClipStats stats = clip_to_surface(sphere, splats, tolerance);
  EXPECT_EQ(stats.shortened, 1u);
  EXPECT_EQ(stats.clipped, 0u);
  EXPECT_TRUE(std::isinf(splats[0].clip_offset));
  EXPECT_NEAR(length(splats[0].major), std::sqrt(2 * tolerance), 0.02);
  EXPECT_FLOAT_EQ(length(splats[0].minor), 0.1f);
  // Never below the minor axis.
  std::vector<SplatRecord> thin{ellipse({0, 0, 1}, {0, 0, 1}, {0.5f, 0, 0}, {0, 0.3f, 0})};
  clip_to_surface(sphere, thin, tolerance);
  EXPECT_FLOAT_EQ(length(thin[0].major), 0.3f);
}

// Distance from a point of the top face's plane z = 1 to the unit cube: its distance to the square.
double off_the_top_face(double x, double y) {
  const double dx = std::max({0.0, -x, x - 1}), dy = std::max({0.0, -y, y - 1});
  return std::hypot(dx, dy);
}

// At a corner the surface keeps a quadrant of a splat's disc (or less), which no single line cuts
// out: a splat on the corner and one beside it are shrunk until their rims stay within the
// tolerance of the cube, instead of being left whole.
TEST(SurfaceClip, ShrinksSplatsAtAConvexCorner) {
  const Surface cube(cube_mesh());
  const double tolerance = 0.005;
  std::vector<SplatRecord> splats{ellipse({1.0f, 1.0f, 1.0f}, {0, 0, 1}, {0.08f, 0, 0}, {0, 0.08f, 0}),
                                  ellipse({0.97f, 0.97f, 1.0f}, {0, 0, 1}, {0.06f, 0.0f, 0}, {0, 0.05f, 0})};
  const SurfaceClipStats stats = clip_to_surface(cube, splats, tolerance);
  EXPECT_EQ(stats.cornered, 2u);
  EXPECT_EQ(stats.clipped, 0u);
  for (const SplatRecord& s : splats) {
    EXPECT_TRUE(std::isinf(s.clip_offset));
    EXPECT_GT(length(s.minor), 0.0f);
    // The rim, finer than the fit's 16 directions: within the tolerance plus what falls between them.
    double worst = 0;
    for (int k = 0; k < 360; ++k) {
      const double t = k * std::numbers::pi / 180;
      const double x = s.center.x + std::cos(t) * s.major.x + std::sin(t) * s.minor.x;
      const double y = s.center.y + std::cos(t) * s.major.y + std::sin(t) * s.minor.y;
      worst = std::max(worst, off_the_top_face(x, y));
    }
    EXPECT_LE(worst, 1.5 * tolerance) << "splat at " << s.center.x << ", " << s.center.y;
  }
}

}  // namespace
}  // namespace splatcl::splats
