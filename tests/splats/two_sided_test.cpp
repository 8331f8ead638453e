// The two-sided bound on the meshes users bring, checked against the surface itself
// (splats/surface_check.hpp, independent of the builder): every point of every splat within ε of
// the surface, every point of the surface within ε of a splat that holds its projection and faces
// its way. Generated hard cases, and the test models when they are present.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "math/dvec3.hpp"
#include "splats/pipeline_options.hpp"
#include "runtime/error.hpp"
#include "splats/surface.hpp"
#include "splats/surface_check.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

struct Outcome {
  SplatRun run;
  std::vector<SplatRecord> splats;
  SurfaceCheckReport report;
};

// The command line's default parameters (splatcl splats) at ε = eps_diag × diagonal, then the check.
Outcome build_and_check(const Mesh& mesh, double eps_diag, Runtime* device, std::size_t surface_points = 300'000) {
  SplatParameters params;
  params.eps_diag = eps_diag;
  const SplatSetup setup = splat_setup(params, mesh, mesh.source);
  Outcome out{generate_splats(mesh, setup.colors, setup.options, device), {}, {}};
  out.splats = out.run.records();
  SurfaceCheckOptions check;
  check.eps = setup.options.fit.eps;
  check.surface_points = surface_points;
  check.seed = 12345;  // not the builder's: the check samples its own points
  out.report = check_surface(mesh, out.splats, check);
  return out;
}

std::string describe(const SurfaceCheckReport& r) {
  return fmt::format("{} splats; uncovered {} of {} points ({} holes, largest {:.3g} eps across); {} splats beyond eps, "
                     "up to {:.4g} eps; {} degenerate; largest major / diagonal {:.3g}",
                     r.splats, r.uncovered_points, r.surface_points, r.holes, r.largest_hole_diameter / r.eps, r.splats_beyond,
                     r.max_distance_eps(), r.degenerate, r.largest_major_diagonal());
}

struct HardCase {
  const char* name;
  Mesh (*make)();
};

const HardCase kHardCases[] = {
    {"low-poly icosphere (320 faces)", [] { return icosphere_mesh(2); }},
    {"planar grid", [] { return plane_mesh(30); }},
    {"cube", [] { return cube_mesh(); }},
    {"creased part", [] { return creased_part_mesh(); }},
    {"thin shell", [] { return thin_shell_mesh(0.004f); }},
    {"400 sliver triangles", [] { return sliver_fan_mesh(400); }},
    {"non-planar quads", [] { return non_planar_quads_mesh(8, 0.12f); }},
    {"inside-out cube", [] { return inside_out_cube_mesh(); }},
};

class TwoSidedBound : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(TwoSidedBound, HoldsOnTheHardCases) {
  const auto [index, eps_diag] = GetParam();
  const HardCase& hard = kHardCases[index];
  const Mesh mesh = hard.make();
  const Outcome out = build_and_check(mesh, eps_diag, &runtime());
  EXPECT_TRUE(out.report.ok()) << hard.name << " at eps_diag " << eps_diag << ": " << describe(out.report);
  // No runaway splats: the longest is at most half the model.
  EXPECT_LE(out.report.largest_major_diagonal(), 0.5) << hard.name;
}

INSTANTIATE_TEST_SUITE_P(Meshes, TwoSidedBound,
                         ::testing::Combine(::testing::Range(0, static_cast<int>(std::size(kHardCases))), ::testing::Values(0.01, 0.003)));

// A box with non-square faces needs about the splats of a cube: the gap splats along a face's border
// tried major axes only at multiples of 45 degrees from their triangle's longest edge (the quad's
// diagonal), none of which runs along the border of a 1 x 2 face, so short ones lined every edge:
// `splatcl splats --eps 0.002` wrote 4,909 splats against the cube's 645, now 687 (this test: 5,396
// against 714 before).
TEST(TwoSidedBound, NonSquareFacesNeedAboutTheSplatsOfSquareOnes) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 1}, {1, 0, 1}, {1, 2, 1}, {0, 2, 1}};
  const Mesh box = make_mesh(v, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}}, "1 x 2 x 1 box");
  const Mesh cube = cube_mesh();
  const double eps = 0.002;
  const Outcome box_out = build_and_check(box, eps / box.bounds().diagonal(), &runtime());
  const Outcome cube_out = build_and_check(cube, eps / cube.bounds().diagonal(), &runtime());
  EXPECT_TRUE(box_out.report.ok()) << describe(box_out.report);
  EXPECT_TRUE(cube_out.report.ok()) << describe(cube_out.report);
  EXPECT_LE(box_out.splats.size(), 3 * cube_out.splats.size() / 2) << "box " << box_out.splats.size() << ", cube " << cube_out.splats.size();
}

// A thin plate is splatted as its two faces are: the kNN graph passed over the other side
// (splats/neighbors.hpp). Before, half of every neighbourhood lay on the other side, growth walked
// a sparse tree of its own, each splat's covered set held half the samples it spans, and selection
// stacked splats: 10 x 10 x 0.05 at eps 0.0141 (`splatcl splats` defaults), 886 splats with 11.7
// times the surface's area (up to 37 deep), against 289 and 2.4 times for the one-quad square
// below; now 736 and 2.9 times. Judged by the splats' area, the check's coverage aside.
TEST(TwoSidedBound, AThinPlateIsSplattedLikeItsFaces) {
  const std::vector<Vec3> v{{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}, {0, 0, 0.05f}, {10, 0, 0.05f}, {10, 10, 0.05f}, {0, 10, 0.05f}};
  const Mesh plate = make_mesh(v, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}},
                               "thin plate");
  const Mesh square = make_mesh({{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}}, {{0, 1, 2, 3}}, "square");
  const double eps = 0.001 * plate.bounds().diagonal();
  const Outcome plate_out = build_and_check(plate, 0.001, &runtime());
  const Outcome square_out = build_and_check(square, eps / square.bounds().diagonal(), &runtime());
  EXPECT_TRUE(plate_out.report.ok()) << describe(plate_out.report);
  EXPECT_TRUE(square_out.report.ok()) << describe(square_out.report);
  const auto area_ratio = [](const std::vector<SplatRecord>& splats, double surface) {
    double sum = 0;
    for (const SplatRecord& s : splats) sum += std::numbers::pi * length(DVec3(s.major)) * length(DVec3(s.minor));
    return sum / surface;
  };
  const double plate_ratio = area_ratio(plate_out.splats, 2 * 100 + 4 * 10 * 0.05);
  const double square_ratio = area_ratio(square_out.splats, 100);
  EXPECT_LE(plate_ratio, 1.5 * square_ratio) << "plate " << plate_ratio << ", square " << square_ratio;
  EXPECT_LE(plate_out.splats.size(), 3 * square_out.splats.size()) << "plate " << plate_out.splats.size() << ", square "
                                                                     << square_out.splats.size();
}

// No needles. The growth's ellipse phase can give a major of 200,000 ε beside a minor of 16 ε
// (samples near the circle's rim, on an octahedron); the surface bound scaled such a splat down
// whole, to a minor of ε/130 and a major of 98 ε (aspect 12,690:1, 25 of them above 100:1). Now
// it shrinks it from 4:1 and extends the major back as far as the surface allows: aspect 176,
// minor 0.87 ε. Bounds for the octahedron and the hard cases: a splat longer than 20:1 has a minor
// of at least ε/8; the aspect is at most a quarter of the diagonal (the gap splats' largest) over ε/2.
TEST(TwoSidedBound, NoNeedles) {
  const Mesh octahedron = make_mesh({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                                    {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}, "octahedron");
  std::vector<std::pair<std::string, Mesh>> meshes{{"octahedron", octahedron}};
  for (const HardCase& hard : kHardCases) meshes.emplace_back(hard.name, hard.make());
  for (const auto& [name, mesh] : meshes) {
    const double eps_diag = 0.001;
    const Outcome out = build_and_check(mesh, eps_diag, &runtime(), 50'000);
    EXPECT_TRUE(out.report.ok()) << name << ": " << describe(out.report);
    const double eps = eps_diag * mesh.bounds().diagonal();
    double worst_aspect = 0, thinnest_long = INFINITY;  // the smallest minor of the splats longer than 20:1
    for (const SplatRecord& splat : out.splats) {
      const double a = length(DVec3(splat.major)), b = length(DVec3(splat.minor));
      worst_aspect = std::max(worst_aspect, a / b);
      if (a > 20 * b) thinnest_long = std::min(thinnest_long, b);
    }
    EXPECT_GE(thinnest_long, eps / 8) << name;
    EXPECT_LE(worst_aspect, 0.25 / (0.5 * eps_diag)) << name;
  }
}

// The device kernels and the native reference give the same splats, gap filling included.
TEST(TwoSidedBound, DeviceAndReferenceAgree) {
  const Mesh mesh = creased_part_mesh();
  const Outcome device = build_and_check(mesh, 0.005, &runtime(), 50'000);
  const Outcome native = build_and_check(mesh, 0.005, nullptr, 50'000);
  ASSERT_EQ(device.splats.size(), native.splats.size());
  for (std::size_t j = 0; j < device.splats.size(); ++j) {
    EXPECT_EQ(device.splats[j].center, native.splats[j].center) << j;
    EXPECT_EQ(device.splats[j].major, native.splats[j].major) << j;
    EXPECT_EQ(device.splats[j].minor, native.splats[j].minor) << j;
  }
}

// The thesis's method alone leaves the holes and runaway splats the extensions remove: the check
// must see them, or it proves nothing about the extensions.
TEST(TwoSidedBound, TheThesisAloneBreaksIt) {
  const Mesh mesh = cube_mesh();
  SplatParameters params;
  params.eps_diag = 0.003;
  params.thesis_only = true;
  params.samples = "vertices";
  const SplatSetup setup = splat_setup(params, mesh, mesh.source);
  const SplatRun run = generate_splats(mesh, setup.colors, setup.options, &runtime());
  SurfaceCheckOptions check;
  check.eps = setup.options.fit.eps;
  check.surface_points = 50'000;
  const SurfaceCheckReport report = check_surface(mesh, run.records(), check);
  EXPECT_FALSE(report.ok());
  EXPECT_GT(report.uncovered_fraction, 0.9) << describe(report);  // 8 corner splats of zero size
}

// Huge and tiny coordinates: the same cube scaled by 1e18 and 1e-18 gives the same splats in
// units of its size (ε keeps its meaning), and the bound holds. Centred and scaled by 1.1e38 (a
// diagonal of 1.9e38, near the float limit) the float rounding estimate overflowed to inf and every
// ε was refused.
TEST(TwoSidedBound, HugeAndTinyCoordinates) {
  const Mesh unit = cube_mesh();
  const Outcome reference = build_and_check(unit, 0.01, &runtime(), 50'000);
  for (const float scale : {1e18f, 1e-18f, 1.1e38f}) {
    const Vec3 offset = scale > 1e30f ? Vec3{-0.5f, -0.5f, -0.5f} : Vec3{3, -2, 1};
    const Mesh scaled = splatcl::testing::moved_mesh(unit, [&](Vec3 p) { return scale * (p + offset); }, "scaled cube");
    const Outcome out = build_and_check(scaled, 0.01, &runtime(), 50'000);
    EXPECT_NE(out.run.scale, 1.0);
    EXPECT_TRUE(out.report.ok()) << scale << ": " << describe(out.report);
    EXPECT_NEAR(static_cast<double>(out.splats.size()), static_cast<double>(reference.splats.size()),
                0.1 * static_cast<double>(reference.splats.size()))
        << scale;
  }
}

// A prism whose top is one non-planar 12-gon, a crown (corners alternately at heights 1 and 1.3):
// its fan triangles stand up to 63° off the polygon's plane. Their samples took normals smoothed
// against the polygon's normal, so near the crown's ridges the side walls' samples outweighed them
// and 6 grown splats faced into the solid (the check passed: gap splats covered the area facing
// the right way). Every splat that lies along a face within 2 ε of its centre must face the way of
// one such face (the faces as the file gives them, fanned from their first corner).
TEST(TwoSidedBound, NonPlanarPolygonSplatsFaceOutward) {
  constexpr int m = 12;
  std::vector<Vec3> vertices;
  for (int k = 0; k < m; ++k) vertices.push_back({static_cast<float>(std::cos(2 * std::numbers::pi * k / m)), static_cast<float>(std::sin(2 * std::numbers::pi * k / m)), 0.0f});
  for (int k = 0; k < m; ++k)
    vertices.push_back({vertices[k].x, vertices[k].y, 1.0f + 0.3f * static_cast<float>(k % 2)});
  std::vector<std::vector<std::uint32_t>> faces(2);
  for (int k = 0; k < m; ++k) faces[0].push_back(static_cast<std::uint32_t>(m - 1 - k)), faces[1].push_back(static_cast<std::uint32_t>(m + k));
  for (std::uint32_t k = 0; k < m; ++k) faces.push_back({k, (k + 1) % m, m + (k + 1) % m, m + k});
  const Mesh crown = make_mesh(vertices, faces, "crown");
  const Outcome out = build_and_check(crown, 0.001, &runtime(), 50'000);
  EXPECT_TRUE(out.report.ok()) << describe(out.report);
  std::vector<SurfaceTriangle> triangles;  // only the corners and the unit normal are set
  for (const auto& face : faces)
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      SurfaceTriangle t{};
      t.a = DVec3(vertices[face[0]]), t.b = DVec3(vertices[face[k]]), t.c = DVec3(vertices[face[k + 1]]);
      t.normal = normalized(cross(t.b - t.a, t.c - t.a));
      triangles.push_back(t);
    }
  const double eps = 0.001 * crown.bounds().diagonal();  // as build_and_check's eps_diag
  std::size_t along_a_face = 0, facing_inward = 0;
  for (const SplatRecord& splat : out.splats) {
    const DVec3 centre(splat.center), n = normalized(DVec3(splat.normal));
    bool parallel = false, agrees = false;
    for (const SurfaceTriangle& t : triangles) {
      if (std::abs(dot(n, t.normal)) < 0.9 || length(closest_point(t, centre) - centre) > 2 * eps) continue;
      parallel = true;
      agrees = agrees || dot(n, t.normal) > 0;
    }
    along_a_face += parallel;
    facing_inward += parallel && !agrees;
  }
  EXPECT_GT(along_a_face, out.splats.size() / 2);
  EXPECT_EQ(facing_inward, 0u) << "of " << along_a_face << " splats along a face";
}

// Gap search on needles: cells are cut across a needle (and a cap at its longest edge), not at
// their edge midpoints, which kept every cell a needle refined to the finest size along its length.
// A fan of 400 needles checked 5,391,919 cells that way; 256,457 now, and its splats keep the bound.
TEST(TwoSidedBound, GapSearchOnNeedlesChecksBoundedCells) {
  const Outcome out = build_and_check(sliver_fan_mesh(400), 0.001, &runtime(), 50'000);
  EXPECT_TRUE(out.report.ok()) << describe(out.report);
  EXPECT_LT(out.run.surface_fit.cells_checked, 1'000'000u);
}

// A scan in georeferenced coordinates: a sphere of radius 100 far from the origin. Written as floats
// its splats move by up to half a float step there (0.03 per coordinate at 1e6, against ε = 0.35):
// fitted to the full ε, 4 of 3,099 splats left the surface by up to 1.004 ε (the run was refused);
// the bound now leaves room for the rounding. Where the steps take more than half of ε (1e7: steps of 1), the
// run is refused before any work, naming the cause.
TEST(TwoSidedBound, FarFromTheOriginKeepsTheBoundAfterFloatRounding) {
  const Mesh unit = sphere_mesh(24, 48);
  const auto placed = [&](float offset) {
    return splatcl::testing::moved_mesh(unit, [&](Vec3 p) { return 100.0f * p + Vec3{offset, offset, offset}; }, fmt::format("sphere at {:g}", offset));
  };
  for (const float offset : {2e5f, 1e6f}) {
    const Outcome out = build_and_check(placed(offset), 0.001, &runtime(), 50'000);
    EXPECT_TRUE(out.report.ok()) << offset << ": " << describe(out.report);
  }
  try {
    build_and_check(placed(1e7f), 0.001, &runtime(), 50'000);
    ADD_FAILURE() << "a sphere at 1e7 was not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("translate the mesh nearer the origin (a scene object: give it a fit) or raise eps (--eps"), std::string::npos) << e.what();
  }
}

// A coloured flat part thinner than a few ε (a sign, a decal, a sheet-metal part): each sample's
// nearest neighbour is the one under it on the other side, 3.5 ε below its splat's plane. As a
// violator it stopped every splat at its start, so the greedy selection had nothing, gap filling
// made the whole cover and its splats, as large as the surface allows, took whatever colour lay
// at their centre: 1,867 of these 2,279 points were held by a splat of another colour. Growth now
// passes over the other side's samples (splat_other_sheet), and every splat keeps to its colour
// (fill_gaps). Checked against the colour field itself at random points of the top face: every
// up-facing splat that holds a point (within ε of its plane, inside its ellipse) must show the
// point's colour within the tolerance, but for points within one sample spacing of a cell face.
TEST(TwoSidedBound, ColouredThinPlateKeepsItsColours) {
  const float thickness = 0.005f;  // 3.5 ε at the default eps_diag
  const Mesh mesh = thin_shell_mesh(thickness);
  SplatParameters params;
  params.color_field = "hard";
  params.color_tol = 10;
  const SplatSetup setup = splat_setup(params, mesh, mesh.source);
  const SplatRun run = generate_splats(mesh, setup.colors, setup.options, &runtime());
  const std::vector<SplatRecord> splats = run.records();
  const float eps = setup.options.fit.eps;
  const double spacing = 0.5 * std::sqrt(eps * setup.diagonal);  // the auto sampling's spacing, at most
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::size_t checked = 0, wrong = 0, uncovered = 0;
  for (int n = 0; n < 4000; ++n) {
    const Vec3 p{unit(random), unit(random), thickness};
    const Rgba8 truth = setup.colors.at(p, nullptr);
    // Near a cell boundary the colour changes within a sample spacing: leave those points out.
    bool near_boundary = false;
    for (const float dx : {-1.0f, 1.0f})
      for (const float dy : {-1.0f, 1.0f}) {
        const Rgba8 c = setup.colors.at(Vec3{p.x + dx * static_cast<float>(spacing), p.y + dy * static_cast<float>(spacing), p.z}, nullptr);
        near_boundary = near_boundary || c.r != truth.r || c.g != truth.g || c.b != truth.b;
      }
    if (near_boundary) continue;
    ++checked;
    bool covered = false, bad = false;
    for (const SplatRecord& s : splats) {
      if (s.normal.z <= 0.5f) continue;
      const Vec3 d = p - s.center;
      if (std::abs(dot(d, s.normal)) > eps) continue;
      const float a = length(s.major), b = length(s.minor);
      if (!(a > 0 && b > 0)) continue;
      const float x = dot(d, s.major) / a, y = dot(d, s.minor) / b;
      if ((x / a) * (x / a) + (y / b) * (y / b) > 1.0f) continue;
      covered = true;
      bad = bad || std::abs(s.color.r - truth.r) > params.color_tol || std::abs(s.color.g - truth.g) > params.color_tol ||
            std::abs(s.color.b - truth.b) > params.color_tol;
    }
    uncovered += covered ? 0 : 1;
    wrong += bad ? 1 : 0;
  }
  ASSERT_GT(checked, 1000u);
  EXPECT_EQ(uncovered, 0u);
  fmt::print("{} of {} points show a wrong colour, {} splats\n", wrong, checked, splats.size());
  EXPECT_LE(wrong, checked / 100) << wrong << " of " << checked << " points show a colour beyond the tolerance ("
                                  << splats.size() << " splats)";
}

// The sample budget: the automatic spacing coarsens to fit it and says so; an explicit spacing and
// the thesis's grid are refused before any sample is made; vertices alone beyond it are refused.
TEST(Sampling, BudgetCoarsensAutoAndRefusesTheRest) {
  const Mesh plane = plane_mesh(4);  // 25 vertices, area 1
  SamplingOptions automatic = parse_sampling("auto");
  automatic.spacing = 0.001;  // about a million grid points
  automatic.coarsen = true;
  automatic.max_samples = 5000;
  const Samples coarse = sample_mesh(plane, automatic, ColorSource{});
  EXPECT_LE(coarse.size(), 5000u);
  EXPECT_GT(coarse.size(), 1000u);  // coarsened, not collapsed
  EXPECT_GT(coarse.grid_spacing, 0.001);
  EXPECT_NE(coarse.note.find("coarsened"), std::string::npos) << coarse.note;
  SamplingOptions explicit_spacing = parse_sampling("spacing:0.001");
  explicit_spacing.max_samples = 5000;
  EXPECT_THROW(sample_mesh(plane, explicit_spacing, ColorSource{}), Error);
  SamplingOptions grid = parse_sampling("grid:1000");
  grid.max_samples = 5000;
  EXPECT_THROW(sample_mesh(plane, grid, ColorSource{}), Error);
  SamplingOptions vertices = parse_sampling("vertices");
  vertices.max_samples = 10;
  EXPECT_THROW(sample_mesh(plane, vertices, ColorSource{}), Error);
  for (const char* bad : {"spacing:", "spacing:0", "spacing:-1", "auto:1"}) EXPECT_THROW(parse_sampling(bad), Error) << bad;
}

// A non-planar polygon is sampled on its fan triangles: every sample lies on the surface.
TEST(Sampling, NonPlanarPolygonsAreSampledOnTheirTriangles) {
  const Mesh mesh = non_planar_quads_mesh(4, 0.3f);
  SamplingOptions options = parse_sampling("spacing:0.02");
  const Samples samples = sample_mesh(mesh, options, ColorSource{});
  ASSERT_GT(samples.size(), 1000u);
  const Surface surface(mesh);
  double worst = 0;
  for (const Vec4& p : samples.positions) worst = std::max(worst, surface.nearest(DVec3(xyz(p))).distance);
  EXPECT_LT(worst, 1e-6);
}

// The growth cap keeps a flat region linear: no splat covers more than max_covered samples, and
// the plane is still covered.
TEST(TwoSidedBound, GrowthCapBoundsEverySplat) {
  const Mesh mesh = plane_mesh(40);  // 1,681 vertices
  SplatParameters params;
  params.samples = "vertices";
  params.max_covered = 64;
  const SplatSetup setup = splat_setup(params, mesh, mesh.source);
  const SplatRun run = generate_splats(mesh, setup.colors, setup.options, &runtime());
  std::size_t largest = 0;
  for (std::size_t j = 0; j < run.fit.covered.size(); ++j) largest = std::max(largest, run.fit.covered.row_size(j));
  EXPECT_LE(largest, 64u);
  SurfaceCheckOptions check;
  check.eps = setup.options.fit.eps;
  check.surface_points = 50'000;
  EXPECT_TRUE(check_surface(mesh, run.records(), check).ok());
}

// The thesis's method has no size cap, but its accepted sets have a memory budget: on a plane,
// where every splat would cover every sample (n² entries), each stops at budget / n samples.
// Without a budget the same run covers the whole plane with every splat.
TEST(ThesisGrowth, AFlatFaceIsCappedByTheSetsBudget) {
  const Mesh mesh = plane_mesh(40);  // 1,681 vertices
  SplatParameters params;
  params.samples = "vertices";
  params.thesis_only = true;
  SplatSetup setup = splat_setup(params, mesh, mesh.source);
  EXPECT_EQ(setup.options.covered_budget, kCoveredBudget);
  const auto largest_set = [](const SplatRun& run) {
    std::size_t largest = 0;
    for (std::size_t j = 0; j < run.fit.covered.size(); ++j) largest = std::max(largest, run.fit.covered.row_size(j));
    return largest;
  };
  setup.options.covered_budget = 0;
  const SplatRun whole = generate_splats(mesh, setup.colors, setup.options, &runtime());
  EXPECT_EQ(largest_set(whole), 1681u);
  setup.options.covered_budget = 1681 * 300;
  const SplatRun capped = generate_splats(mesh, setup.colors, setup.options, &runtime());
  EXPECT_EQ(capped.max_covered, 300u);
  EXPECT_EQ(largest_set(capped), 300u);
  EXPECT_LE(capped.fit.covered.items.size(), std::size_t{1681} * 300);
  EXPECT_EQ(capped.after.uncovered, 0u);
  // Tiny budgets still let a splat grow kMinBudgetCap samples.
  EXPECT_EQ(budget_growth_cap(1'000'000, kMaxCoveredLimit, 1000), kMinBudgetCap);
  EXPECT_EQ(budget_growth_cap(10, 64, kCoveredBudget), 64u);
  // A cap given with the thesis's method is the cap, and no budget is applied over it.
  params.max_covered = 50;
  setup = splat_setup(params, mesh, mesh.source);
  EXPECT_EQ(setup.options.covered_budget, 0u);
  const SplatRun given = generate_splats(mesh, setup.colors, setup.options, &runtime());
  EXPECT_EQ(given.max_covered, 50u);
  EXPECT_EQ(largest_set(given), 50u);
}

// The test models at two ε (Release only: under the sanitizers this would take many minutes).
TEST(TwoSidedBound, HoldsOnTheSharedModels) {
  if (kSanitized) GTEST_SKIP() << "the test models are checked in the Release build";
  bool any = false;
  for (const char* name : {"stanford-bunny.obj", "fandisk.obj", "spot.obj", "teapot.obj", "rocker-arm.obj", "homer.obj",
                           "nefertiti.obj", "ogre.obj"}) {
    const std::string path = model_path(name);
    if (path.empty()) continue;
    any = true;
    const Mesh mesh = load_mesh(path);
    for (const double eps_diag : {0.004, 0.0015}) {
      const Outcome out = build_and_check(mesh, eps_diag, &runtime(), 400'000);
      EXPECT_TRUE(out.report.ok()) << name << " at eps_diag " << eps_diag << ": " << describe(out.report);
    }
  }
  if (!any) GTEST_SKIP() << "the test models are not in " << SPLATCL_MODELS_DIR;
}

}  // namespace
}  // namespace splatcl::splats
