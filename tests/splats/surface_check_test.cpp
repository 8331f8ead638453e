// `splats verify`'s two-sided bound, against splat sets built by hand whose truth is known
// analytically (or by a fine grid): coverage holes, facing, lifted, tilted, runaway, clipped and
// tangent splats, determinism and the default point count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "runtime/error.hpp"
#include "splats/surface.hpp"
#include "splats/surface_check.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

SplatRecord circle(Vec3 centre, float r, Vec3 normal = {0, 0, 1}) {
  SplatRecord s;
  s.center = centre, s.normal = normal, s.major = {r, 0, 0}, s.minor = {0, r, 0};
  return s;
}

// A grid of circles of radius r = 0.045 at spacing 1/17 (< r √2) over [0, 1]², centres on the
// square's edges too, so no circle leaves the square by more than r < ε = 0.05.
constexpr unsigned kIntervals = 17;
constexpr float kRadius = 0.045f;
constexpr double kEps = 0.05;

std::vector<SplatRecord> grid(Vec3 normal = {0, 0, 1}) {
  std::vector<SplatRecord> splats;
  for (unsigned y = 0; y <= kIntervals; ++y)
    for (unsigned x = 0; x <= kIntervals; ++x)
      splats.push_back(circle({static_cast<float>(x) / kIntervals, static_cast<float>(y) / kIntervals, 0.0f}, kRadius, normal));
  return splats;
}
constexpr unsigned kHole = 8 * (kIntervals + 1) + 8;  // the circle at (8/17, 8/17)

SurfaceCheckOptions options(std::size_t points = 0, double eps = kEps) {
  SurfaceCheckOptions o;
  o.eps = eps;
  o.surface_points = points;
  return o;
}

TEST(SurfaceCheck, CoveringGridIsOkAndCountsItsPoints) {
  const Mesh plane = testing::plane_mesh(4);
  const std::vector<SplatRecord> splats = grid();
  const SurfaceCheckReport report = check_surface(plane, splats, options(200'000));
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.uncovered_points, 0u);
  EXPECT_EQ(report.holes, 0u);
  EXPECT_EQ(report.surface_points, 200'000u);
  EXPECT_NEAR(report.surface_area, 1.0, 1e-12);
  EXPECT_EQ(report.splats, splats.size());
  // 64 interior points, 32 rim points (2π r / ε < 32) and 3 × 8 refining the rim's farthest, per circle.
  EXPECT_EQ(report.splat_points, splats.size() * (64 + 32 + 24));
  EXPECT_EQ(report.splats_beyond, 0u);
  EXPECT_EQ(report.flipped, 0u);
  EXPECT_EQ(report.degenerate, 0u);
  // The circles on the edges reach r beyond the square; nothing reaches farther.
  EXPECT_LE(report.max_distance, kRadius * (1 + 1e-6));
  EXPECT_GT(report.max_distance, 0.9 * kRadius);
  EXPECT_DOUBLE_EQ(report.area_beyond_fraction, 0.0);
}

TEST(SurfaceCheck, RemovedCircleLeavesAHoleOfItsArea) {
  const Mesh plane = testing::plane_mesh(4);
  std::vector<SplatRecord> splats = grid();
  splats.erase(splats.begin() + kHole);
  // The truth on a fine grid around the removed centre: the points no remaining circle covers.
  const double s = 1.0 / kIntervals, h = 2e-5;
  std::size_t inside = 0;
  double reach = 0;
  for (double y = -s; y <= s; y += h)
    for (double x = -s; x <= s; x += h) {
      bool covered = false;
      for (int dy = -1; dy <= 1 && !covered; ++dy)
        for (int dx = -1; dx <= 1 && !covered; ++dx)
          if (dx != 0 || dy != 0) covered = std::hypot(x - dx * s, y - dy * s) <= kRadius;
      if (covered) continue;
      ++inside;
      reach = std::max(reach, std::hypot(x, y));
    }
  const double hole_area = static_cast<double>(inside) * h * h;
  const double hole_diameter = 2 * reach;  // the hole is symmetric about the removed centre
  ASSERT_GT(hole_area, 5e-4);

  const SurfaceCheckReport report = check_surface(plane, splats, options(2'000'000));
  EXPECT_FALSE(report.ok());
  // One hole; its sharp tips between neighbouring circles may leave a stray point or two unlinked.
  EXPECT_GE(report.holes, 1u);
  EXPECT_LE(report.holes, 4u);
  EXPECT_GE(static_cast<double>(report.largest_hole_points), 0.99 * static_cast<double>(report.uncovered_points));
  EXPECT_NEAR(report.uncovered_fraction, hole_area, 0.1 * hole_area);  // the plane's area is 1
  EXPECT_NEAR(report.largest_hole_area, hole_area, 0.1 * hole_area);
  EXPECT_NEAR(report.largest_hole_diameter, hole_diameter, 0.3 * hole_diameter);
  EXPECT_LE(report.largest_hole_diameter, hole_diameter);  // a lower bound: the points lie inside the hole
  EXPECT_EQ(report.splats_beyond, 0u);
}

TEST(SurfaceCheck, FlippedNormalsCoverNothing) {
  const Mesh plane = testing::plane_mesh(4);
  const std::vector<SplatRecord> splats = grid({0, 0, -1});
  const SurfaceCheckReport report = check_surface(plane, splats, options(50'000));
  EXPECT_FALSE(report.ok());
  EXPECT_EQ(report.uncovered_points, report.surface_points);
  EXPECT_DOUBLE_EQ(report.uncovered_fraction, 1.0);
  EXPECT_EQ(report.flipped, splats.size());
  EXPECT_EQ(report.holes, 1u);
  EXPECT_NEAR(report.largest_hole_area, 1.0, 1e-12);
  EXPECT_NEAR(report.largest_hole_diameter, std::sqrt(2.0), 0.02);
  EXPECT_EQ(report.splats_beyond, 0u);  // the splats themselves lie on the surface
}

TEST(SurfaceCheck, LiftedSplatIsTwoEpsAway) {
  const Mesh plane = testing::plane_mesh(4);
  const float lift = static_cast<float>(2 * kEps);
  const SurfaceCheckReport report = check_surface(plane, {circle({0.5f, 0.5f, lift}, 0.2f)}, options(20'000));
  EXPECT_FALSE(report.ok());
  EXPECT_NEAR(report.max_distance, 2 * kEps, 2 * kEps * 1e-6);
  EXPECT_NEAR(report.max_distance_eps(), 2.0, 1e-6);
  EXPECT_EQ(report.splats_beyond, 1u);
  EXPECT_DOUBLE_EQ(report.area_beyond_fraction, 1.0);
  EXPECT_EQ(report.worst_splat, 0u);
}

// The check `splats` and `batch` run before writing: splats that break the bound the run promised
// stop it with one line naming the model and what broke; a run that promised nothing gets the report.
TEST(SurfaceCheck, CheckBeforeWritingRefusesWhatBreaksThePromisedBound) {
  const Mesh plane = testing::plane_mesh(1);
  std::vector<SplatRecord> splats = grid();
  splats[kHole].center.z = static_cast<float>(2 * kEps);  // one splat lifted off the square
  try {
    check_before_writing(plane, splats, true, kEps, "square.obj", " (remedy)");
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("square.obj: the splats break the two-sided bound at eps 0.05 ("), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1 splat leaves the surface by more than eps (up to 2 eps)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nothing written (remedy)"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(check_before_writing(plane, splats, false, kEps, "square.obj", "").ok());
  EXPECT_TRUE(check_before_writing(plane, grid(), true, kEps, "square.obj", "").ok());
}

TEST(SurfaceCheck, TiltedSplatWithRimHalfEpsOffIsOk) {
  const Mesh plane = testing::plane_mesh(4);
  std::vector<SplatRecord> splats = grid();
  const double a = 0.3, sine = 0.5 * kEps / a, cosine = std::sqrt(1 - sine * sine);
  SplatRecord tilted;
  tilted.center = {0.5f, 0.5f, 0.0f};
  tilted.major = {static_cast<float>(a * cosine), 0.0f, static_cast<float>(a * sine)};
  tilted.minor = {0.0f, 0.2f, 0.0f};
  tilted.normal = {static_cast<float>(-sine), 0.0f, static_cast<float>(cosine)};
  splats.push_back(tilted);
  EXPECT_TRUE(check_surface(plane, splats, options(100'000)).ok());
  const SurfaceCheckReport alone = check_surface(plane, {tilted}, options(20'000));
  EXPECT_NEAR(alone.max_distance, 0.5 * kEps, 0.5 * kEps * 1e-5);  // the rim point at the major axis' end
  EXPECT_EQ(alone.splats_beyond, 0u);
  EXPECT_DOUBLE_EQ(alone.area_beyond_fraction, 0.0);
}

TEST(SurfaceCheck, RimMaximumBetweenRimSamplesIsFound) {
  // A circle tilted so its rim's height is r sin α cos(φ + φ0), peaking at φ = −φ0: half-way
  // between two of the 32 rim samples, where they alone would miss 1 − cos(π / 32) = 0.5 %.
  const Mesh plane = testing::plane_mesh(4);
  const double r = 0.3, sine = 0.5 * kEps / r, cosine = std::sqrt(1 - sine * sine), phi0 = std::numbers::pi / 32;
  const DVec3 n{-sine, 0, cosine}, g{cosine, 0, sine}, w{0, 1, 0};
  const DVec3 u = std::cos(phi0) * g + std::sin(phi0) * w, v = cross(n, u);
  SplatRecord tilted;
  tilted.center = {0.5f, 0.5f, 0.0f}, tilted.normal = to_float(n), tilted.major = to_float(r * u), tilted.minor = to_float(r * v);
  const SurfaceCheckReport report = check_surface(plane, {tilted}, options(20'000));
  EXPECT_NEAR(report.max_distance, r * sine, r * sine * 1e-5);
}

TEST(SurfaceCheck, RunawaySplatShareBeyondEpsIsTheAnalyticOne) {
  const Mesh plane = testing::plane_mesh(4);
  const double a = 10, b = 0.3;  // major 10× the square's side, minor inside it
  SplatRecord runaway;
  runaway.center = {0.5f, 0.5f, 0.0f};
  runaway.major = {static_cast<float>(a), 0, 0}, runaway.minor = {0, static_cast<float>(b), 0}, runaway.normal = {0, 0, 1};
  SurfaceCheckOptions o = options(20'000);
  o.ellipse_points = 100'000;
  const SurfaceCheckReport report = check_surface(plane, {runaway}, o);
  // Within ε of the square: |x| <= X around the centre (|y| <= b stays inside the square).
  const double X = 0.5 + kEps * (1 + o.slack);
  const double near = 2 * b * (X * std::sqrt(1 - X * X / (a * a)) + a * std::asin(X / a));
  const double beyond = 1 - near / (std::numbers::pi * a * b);
  EXPECT_NEAR(report.area_beyond_fraction, beyond, 0.05 * beyond);
  EXPECT_DOUBLE_EQ(report.largest_major, a);
  EXPECT_DOUBLE_EQ(report.diagonal, std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(report.largest_major_diagonal(), a / std::sqrt(2.0));
  // Far past the 16 ε limit: the worst point's true distance, the major axis' end 9.5 from the edge.
  EXPECT_NEAR(report.max_distance, a - 0.5, 1e-6);
  EXPECT_EQ(report.splats_beyond, 1u);
  EXPECT_FALSE(report.ok());
}

TEST(SurfaceCheck, HugeSplatIsMeasuredNotOverflowed) {
  const Mesh plane = testing::plane_mesh(1);
  SplatRecord huge = circle({0.5f, 0.5f, 0.0f}, 1e30f);
  const SurfaceCheckReport report = check_surface(plane, {huge}, options(10'000));
  EXPECT_EQ(report.degenerate, 0u);
  EXPECT_EQ(report.uncovered_points, 0u);
  EXPECT_EQ(report.splats_beyond, 1u);
  EXPECT_NEAR(report.max_distance, 1e30, 1e24);
  EXPECT_EQ(report.splat_points, 64u + 512);  // no rim refinement past the 16 eps search limit
}

TEST(SurfaceCheck, ClipKeepsASplatOnTheSurface) {
  const Mesh plane = testing::plane_mesh(4);
  std::vector<SplatRecord> splats = grid();
  SplatRecord edge = circle({0.98f, 0.5f, 0.0f}, 0.2f);  // reaches x = 1.18 unclipped
  edge.clip_x = 1, edge.clip_y = 0, edge.clip_offset = 0.06f;  // keeps x <= 1.04: 0.04 < ε off the square
  splats.push_back(edge);
  const SurfaceCheckReport clipped = check_surface(plane, splats, options(50'000));
  EXPECT_TRUE(clipped.ok());
  EXPECT_EQ(clipped.splats_beyond, 0u);
  EXPECT_NEAR(check_surface(plane, {edge}, options(20'000)).max_distance, 0.04, 1e-6);  // the clip chord

  splats.back().clip_offset = INFINITY;
  const SurfaceCheckReport unclipped = check_surface(plane, splats, options(50'000));
  EXPECT_FALSE(unclipped.ok());
  EXPECT_EQ(unclipped.splats_beyond, 1u);
  EXPECT_NEAR(unclipped.max_distance, 0.18, 1e-6);
  EXPECT_EQ(unclipped.uncovered_points, 0u);
}

TEST(SurfaceCheck, ClippedOffPartCoversNothing) {
  const Mesh plane = testing::plane_mesh(4);
  SplatRecord half = circle({0.5f, 0.5f, 0.0f}, 0.75f);  // covers the square unclipped
  EXPECT_EQ(check_surface(plane, {half}, options(20'000)).uncovered_points, 0u);
  half.clip_x = 1, half.clip_y = 0, half.clip_offset = 0;  // keeps x <= 0.5
  const SurfaceCheckReport report = check_surface(plane, {half}, options(200'000));
  EXPECT_NEAR(report.uncovered_fraction, 0.5, 0.01);
  EXPECT_EQ(report.holes, 1u);
  EXPECT_NEAR(report.largest_hole_diameter, std::hypot(0.5, 1.0), 0.01);
}

TEST(SurfaceCheck, DegenerateSplatsAreCountedAndFail) {
  const Mesh plane = testing::plane_mesh(4);
  std::vector<SplatRecord> splats = grid();
  splats.push_back(circle({NAN, 0.5f, 0.0f}, 0.1f));
  SplatRecord flat = circle({0.5f, 0.5f, 0.0f}, 0.1f);
  flat.minor = {0, 0, 0};
  splats.push_back(flat);
  SplatRecord empty = circle({0.5f, 0.5f, 0.0f}, 0.1f);
  empty.clip_x = 1, empty.clip_offset = -0.2f;  // the clip keeps nothing
  splats.push_back(empty);
  const SurfaceCheckReport report = check_surface(plane, splats, options(20'000));
  EXPECT_EQ(report.degenerate, 3u);
  EXPECT_EQ(report.uncovered_points, 0u);
  EXPECT_EQ(report.splats_beyond, 0u);
  EXPECT_FALSE(report.ok());
}

TEST(SurfaceCheck, TangentSplatsOnASphereAreTheirRimHeightAway) {
  const Mesh sphere = testing::sphere_mesh(24, 48);
  const Surface surface(sphere);
  // The faceting error: the mesh lies between radius 1 − δ and 1 (its vertices are on the sphere).
  double inner = INFINITY;
  for (const SurfaceTriangle& t : surface.triangles()) inner = std::min(inner, length(closest_point(t, DVec3{})));
  const double delta = 1 - inner;
  const double r = 0.3, rim = std::sqrt(1 + r * r) - 1;
  ASSERT_LT(delta, rim / 4);
  std::vector<SplatRecord> splats;
  for (const Vec3 v : sphere.vertices) {
    const DVec3 n = normalized(DVec3(v));
    const DVec3 t1 = normalized(cross(n, std::fabs(n.z) < 0.9 ? DVec3{0, 0, 1} : DVec3{1, 0, 0})), t2 = cross(n, t1);
    SplatRecord s;
    s.center = v, s.normal = to_float(n), s.major = to_float(r * t1), s.minor = to_float(r * t2);
    splats.push_back(s);
  }
  const SurfaceCheckReport report = check_surface(sphere, splats, options(20'000, 0.1));
  // A rim point at radius R = √(1 + r²) is at least R − 1 and at most R − (1 − δ) from the mesh.
  EXPECT_GE(report.max_distance, rim - 1e-6);
  EXPECT_LE(report.max_distance, rim + delta + 1e-6);
  EXPECT_EQ(report.flipped, 0u);
  EXPECT_EQ(report.uncovered_points, 0u);
}

// At an octahedron's tip four faces tie for nearest to a centre just above it. A splat lying on
// one face (its normal) faces the opposite face's way by −1/3: it is not flipped, whichever face
// the search picks. One facing down at the tip is flipped by every face.
TEST(SurfaceCheck, SplatAtAVertexIsFlippedOnlyAgainstEveryNearestFace) {
  const Mesh octahedron = make_mesh({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                                    {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}, "octahedron");
  const Surface surface(octahedron);
  std::vector<SplatRecord> splats;
  // Each face at the tip (0, 1, 0): its outward normal, and a splat on it, centred just above the tip.
  for (const SurfaceTriangle& t : surface.triangles()) {
    if (!(t.normal.y > 0)) continue;
    const DVec3 along = normalized(cross(t.normal, DVec3{0, 1, 0}));
    SplatRecord s;
    s.center = {0.0f, 1.0f + 1e-4f, 0.0f}, s.normal = to_float(t.normal);
    s.major = to_float(0.05 * along), s.minor = to_float(0.05 * cross(t.normal, along));
    splats.push_back(s);
  }
  ASSERT_EQ(splats.size(), 4u);
  SurfaceCheckReport report = check_surface(octahedron, splats, options(10'000, 0.1));
  EXPECT_EQ(report.flipped, 0u);
  splats.push_back(circle({0.0f, 1.0f + 1e-4f, 0.0f}, 0.05f, {0, -1, 0}));
  splats.back().major = {0.05f, 0, 0}, splats.back().minor = {0, 0, 0.05f};
  report = check_surface(octahedron, splats, options(10'000, 0.1));
  EXPECT_EQ(report.flipped, 1u);
  // Nearest the two faces on the +z side, facing against them, and their way by 67° only (cosine
  // 0.39 with the two faces on the -z side): flipped, as no face lies within 60° of its plane.
  const DVec3 tilted = normalized(DVec3{0, -0.3, -1});
  splats.push_back(circle({0.0f, 1.0f + 1e-4f, 1e-3f}, 0.05f, to_float(tilted)));
  splats.back().major = {0.05f, 0, 0}, splats.back().minor = to_float(0.05 * cross(tilted, DVec3{1, 0, 0}));
  report = check_surface(octahedron, splats, options(10'000, 0.1));
  EXPECT_EQ(report.flipped, 2u);
}

// A part thinner than ε (or two parts that touch): a splat of its top sheet lying within ε of it
// can be nearer the bottom sheet, which faces the other way. It is not flipped (the ogre's teeth in
// its gums counted 562 such). One facing down on the top of a part thicker than ε is.
TEST(SurfaceCheck, SplatNearerAnOppositeSheetIsNotFlipped) {
  std::vector<SplatRecord> splats;
  for (unsigned y = 1; y < kIntervals; ++y)
    for (unsigned x = 1; x < kIntervals; ++x)
      splats.push_back(circle({static_cast<float>(x) / kIntervals, static_cast<float>(y) / kIntervals, static_cast<float>(0.1 * kEps)}, kRadius));
  const SurfaceCheckReport thin = check_surface(testing::thin_shell_mesh(static_cast<float>(0.3 * kEps)), splats, options(10'000));
  EXPECT_EQ(thin.flipped, 0u);
  for (SplatRecord& s : splats) s.center.z = static_cast<float>(3 * kEps), s.normal = {0, 0, -1};
  const SurfaceCheckReport thick = check_surface(testing::thin_shell_mesh(static_cast<float>(3 * kEps)), splats, options(10'000));
  EXPECT_EQ(thick.flipped, splats.size());
}

// Far from the origin a mesh reads onto a coarse float grid, and the check measures against that:
// the failure names it (its warning was printed only when a command succeeded).
TEST(SurfaceCheck, FailureNamesTheMeshsCoarseFloats) {
  Mesh far = testing::plane_mesh(4);
  for (Vec3& v : far.vertices) v.x += 1e6f;
  std::vector<SplatRecord> splats = grid({0, 0, -1});
  for (SplatRecord& s : splats) s.center.x += 1e6f;
  const SurfaceCheckReport report = check_surface(far, splats, options(10'000));
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(describe_failure(report).find("floats step"), std::string::npos);
  EXPECT_NE(describe_failure(report, &far).find("floats step by 0.0625"), std::string::npos) << describe_failure(report, &far);
  const Mesh near = testing::plane_mesh(4);
  EXPECT_EQ(describe_failure(check_surface(near, grid({0, 0, -1}), options(10'000)), &near).find("floats step"), std::string::npos);
}

TEST(SurfaceCheck, SameSeedSameReportOtherSeedSimilar) {
  const Mesh plane = testing::plane_mesh(4);
  std::vector<SplatRecord> splats = grid();
  splats.erase(splats.begin() + kHole);
  const SurfaceCheckReport first = check_surface(plane, splats, options(300'000));
  const SurfaceCheckReport again = check_surface(plane, splats, options(300'000));
  EXPECT_EQ(to_json(first).dump(), to_json(again).dump());
  SurfaceCheckOptions other = options(300'000);
  other.seed = 2;
  const SurfaceCheckReport second = check_surface(plane, splats, other);
  EXPECT_NE(first.uncovered_points, second.uncovered_points);
  EXPECT_NEAR(second.uncovered_fraction, first.uncovered_fraction, 0.2 * first.uncovered_fraction);
  EXPECT_LE(second.holes, 4u);
  EXPECT_NEAR(second.largest_hole_diameter, first.largest_hole_diameter, 0.2 * first.largest_hole_diameter);
}

TEST(SurfaceCheck, DefaultPointCountIsTheFormula) {
  EXPECT_EQ(default_surface_points(1.0, 0.005), static_cast<std::size_t>(std::ceil(5 / (std::numbers::pi * 0.005 * 0.005))));
  EXPECT_EQ(default_surface_points(1.0, 0.005), 63'662u);
  EXPECT_EQ(default_surface_points(1.0, 0.5), kMinSurfacePoints);
  EXPECT_EQ(default_surface_points(1e6, 1e-3), kMaxSurfacePoints);
  const Mesh plane = testing::plane_mesh(4, 2.0f);  // area 4
  const std::vector<SplatRecord> none;
  SurfaceCheckReport report = check_surface(plane, none, options(0, 0.01));
  EXPECT_EQ(report.surface_points, static_cast<std::size_t>(std::ceil(5 * 4.0 / (std::numbers::pi * 1e-4))));
  EXPECT_NEAR(report.surface_points_wanted, 5 * 4.0 / (std::numbers::pi * 1e-4), 1e-6);
  EXPECT_FALSE(report.surface_points_clamped);
  EXPECT_EQ(report.uncovered_points, report.surface_points);
  report = check_surface(plane, none, options(0, 0.5));
  EXPECT_EQ(report.surface_points, kMinSurfacePoints);
  EXPECT_TRUE(report.surface_points_clamped);
}

TEST(SurfaceCheck, BadOptionsThrow) {
  const Mesh plane = testing::plane_mesh(1);
  EXPECT_THROW(check_surface(plane, {}, options(0, 0.0)), Error);
  EXPECT_THROW(check_surface(plane, {}, options(0, NAN)), Error);
  EXPECT_THROW(check_surface(plane, {}, options(0, INFINITY)), Error);
}

}  // namespace
}  // namespace splatcl::splats
