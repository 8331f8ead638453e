// Phong splats' normal fields (splats/normal_field.hpp) against analytic truth, not against the
// mesh normals they are fitted to: on a faceted sphere the field follows the true sphere's normals
// far closer than the flat facet normal does; beside a cube's edges it stays flat (no rounding
// across a crease), on either winding; far from the surface or degenerate, a splat stays flat.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "splats/normal_field.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

double angle_degrees(DVec3 a, DVec3 b) {
  const double c = dot(normalized(a), normalized(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

DVec3 field_normal(const NormalField& f, double x, double y) {
  return normalized(DVec3(f.centre) + x * DVec3(f.du) + y * DVec3(f.dv));
}

// A splat at the facet's point nearest to the true sphere point d: the facet's normal, its frame in
// the facet's plane (the flat splat a splat generator would make there).
SplatRecord facet_splat(const Surface& surface, DVec3 d, double a, double b, double turn) {
  const Surface::Nearest near = surface.nearest(d);
  const SurfaceTriangle& t = surface.triangles()[near.triangle];
  const DVec3 q = closest_point(t, d);
  const DVec3 n = dot(t.normal, q) < 0 ? -1.0 * t.normal : t.normal;
  const DVec3 e1 = any_perpendicular(n), e2 = cross(n, e1);
  const DVec3 u = std::cos(turn) * e1 + std::sin(turn) * e2, v = cross(n, u);
  SplatRecord s;
  s.center = to_float(q), s.normal = to_float(n), s.major = to_float(a * u), s.minor = to_float(b * v);
  return s;
}

TEST(NormalField, FollowsTheTrueSphereOnALowPolyMesh) {
  for (const unsigned levels : {1u, 2u}) {
    const Mesh mesh = icosphere_mesh(levels);  // 80 and 320 flat faces on the unit sphere
    const Surface surface(mesh);
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> uniform(0.0, 2.0 * std::numbers::pi);
    const double a = levels == 1 ? 0.18 : 0.09, b = 0.7 * a;
    std::vector<SplatRecord> splats;
    for (int i = 0; i < 400; ++i) splats.push_back(facet_splat(surface, normalized(DVec3(gauss(rng), gauss(rng), gauss(rng))), a, b, uniform(rng)));
    NormalFieldStats stats;
    const std::vector<NormalField> fields = fit_normal_fields(mesh, surface, splats, {}, 60.0f, &stats);
    ASSERT_EQ(fields.size(), splats.size());
    EXPECT_EQ(stats.fitted, splats.size());
    double field_sum = 0, flat_sum = 0, field_max = 0;
    std::size_t points = 0;
    for (std::size_t i = 0; i < splats.size(); ++i) {
      const SplatRecord& s = splats[i];
      for (const auto& [x, y] : {std::pair{0.0, 0.0}, {0.7, 0.0}, {-0.7, 0.0}, {0.0, 0.7}, {0.0, -0.7}, {0.5, 0.5}, {-0.5, -0.5}}) {
        const DVec3 p = DVec3(s.center) + x * DVec3(s.major) + y * DVec3(s.minor);
        const DVec3 truth = normalized(p);  // the true sphere's normal under the point
        const double field = angle_degrees(field_normal(fields[i], x, y), truth);
        field_sum += field, field_max = std::max(field_max, field);
        flat_sum += angle_degrees(DVec3(s.normal), truth);
        ++points;
      }
    }
    const double field_mean = field_sum / static_cast<double>(points), flat_mean = flat_sum / static_cast<double>(points);
    std::printf("icosphere level %u: mean angle to the true normal %.2f° (flat splats %.2f°), worst %.2f°\n", levels, field_mean,
                flat_mean, field_max);
    EXPECT_LT(field_mean, 0.1 * flat_mean);
    EXPECT_LT(field_max, 3.0);
  }
}

TEST(NormalField, StaysFlatBesideSharpEdgesOnEitherWinding) {
  for (const bool inside_out : {false, true}) {
    const Mesh mesh = inside_out ? inside_out_cube_mesh() : cube_mesh();
    const Surface surface(mesh);
    for (const float side : {1.0f, -1.0f}) {  // the splat's normal either way: fields turn to its side
      std::vector<SplatRecord> splats;
      // On the top face (z = 1), reaching over the edge y = 1, over the corner (1, 1, 1), and inside.
      for (const auto& [cx, cy] : {std::pair{0.5f, 0.97f}, {0.95f, 0.95f}, {0.5f, 0.5f}}) {
        SplatRecord s;
        s.center = {cx, cy, 1.0f}, s.normal = {0, 0, side}, s.major = {0.1f, 0, 0}, s.minor = {0, 0.08f, 0};
        splats.push_back(s);
      }
      NormalFieldStats stats;
      const std::vector<NormalField> fields = fit_normal_fields(mesh, surface, splats, {}, 60.0f, &stats);
      EXPECT_EQ(stats.fitted, splats.size());
      for (const NormalField& f : fields)
        for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.7, 0.7}})
          EXPECT_LT(angle_degrees(field_normal(f, x, y), {0, 0, side}), 1e-3) << "inside out " << inside_out << ", side " << side;
    }
  }
}

TEST(NormalField, FarOrDegenerateSplatsStayFlat) {
  const Mesh mesh = sphere_mesh(8, 16);
  const Surface surface(mesh);
  SplatRecord far;
  far.center = {5, 5, 5}, far.normal = {0, 0, 1}, far.major = {0.1f, 0, 0}, far.minor = {0, 0.1f, 0};
  SplatRecord zero;
  zero.center = {0, 0, 1}, zero.normal = {0, 0, 1};
  NormalFieldStats stats;
  const auto fields = fit_normal_fields(mesh, surface, {far, zero}, {}, 60.0f, &stats);
  ASSERT_EQ(fields.size(), 2u);
  EXPECT_EQ(stats.flat, 2u);
  for (const NormalField& f : fields) {
    EXPECT_EQ(f.centre.z, 1.0f);
    EXPECT_EQ(length(f.du), 0.0f);
    EXPECT_EQ(length(f.dv), 0.0f);
  }
  EXPECT_TRUE(fit_normal_fields(mesh, surface, {}, {}, 60.0f).empty());
}

}  // namespace
}  // namespace splatcl::splats
