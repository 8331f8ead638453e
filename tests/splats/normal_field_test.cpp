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

// The fit works in ellipse coordinates, so it is the same at any scale: the icosphere of 80 facets
// scaled to radius 10⁻¹² and 10¹², and splats on such spheres fitted from their neighbours, give
// fields as close to the true sphere as at radius 1.
TEST(NormalField, HugeAndTinyCoordinatesFitTheSame) {
  double mesh_worst[3] = {0, 0, 0}, splat_worst[3] = {0, 0, 0};
  const double scales[3] = {1.0, 1e-12, 1e12};
  for (int k = 0; k < 3; ++k) {
    const double scale = scales[k];
    Mesh mesh = icosphere_mesh(1);
    for (Vec3& v : mesh.vertices) v = to_float(scale * DVec3(v));
    const Surface surface(mesh);
    std::mt19937 rng(5);
    std::normal_distribution<double> gauss;
    std::vector<SplatRecord> splats;
    for (int i = 0; i < 100; ++i)
      splats.push_back(facet_splat(surface, scale * normalized(DVec3(gauss(rng), gauss(rng), gauss(rng))), 0.18 * scale, 0.12 * scale, 0.3 * i));
    NormalFieldStats stats;
    const std::vector<NormalField> fields = fit_normal_fields(mesh, surface, splats, {}, 60.0f, &stats);
    EXPECT_EQ(stats.fitted, splats.size()) << "scale " << scale;
    for (std::size_t i = 0; i < splats.size(); ++i)
      for (const auto& [x, y] : {std::pair{0.0, 0.0}, {0.7, 0.0}, {0.0, -0.7}}) {
        const DVec3 p = DVec3(splats[i].center) + x * DVec3(splats[i].major) + y * DVec3(splats[i].minor);
        mesh_worst[k] = std::max(mesh_worst[k], angle_degrees(field_normal(fields[i], x, y), normalized(p)));
      }
    std::vector<SplatRecord> on_sphere;  // a splat file's splats: on the true sphere, true normals
    for (int i = 0; i < 1000; ++i) {
      const DVec3 d = normalized(DVec3(gauss(rng), gauss(rng), gauss(rng))), u = any_perpendicular(d);
      SplatRecord s;
      s.center = to_float(scale * d), s.normal = to_float(d), s.major = to_float(0.1 * scale * u), s.minor = to_float(0.08 * scale * cross(d, u));
      on_sphere.push_back(s);
    }
    NormalFieldStats from_splats;
    const std::vector<NormalField> splat_fields = fit_normal_fields_from_splats(on_sphere, 60.0f, &from_splats);
    EXPECT_GE(from_splats.fitted, on_sphere.size() * 99 / 100) << "scale " << scale;
    for (std::size_t i = 0; i < on_sphere.size(); ++i) {
      const DVec3 p = DVec3(on_sphere[i].center) + 0.8 * DVec3(on_sphere[i].major);
      splat_worst[k] = std::max(splat_worst[k], angle_degrees(field_normal(splat_fields[i], 0.8, 0.0), normalized(p)));
    }
  }
  std::printf("worst angle to the true sphere at radius 1, 1e-12, 1e12: mesh fit %.3f° %.3f° %.3f°, from splats %.3f° %.3f° %.3f°\n",
              mesh_worst[0], mesh_worst[1], mesh_worst[2], splat_worst[0], splat_worst[1], splat_worst[2]);
  EXPECT_LT(mesh_worst[0], 3.0);
  EXPECT_LT(splat_worst[0], 6.0);
  for (int k = 1; k < 3; ++k) {
    EXPECT_NEAR(mesh_worst[k], mesh_worst[0], 0.01);
    EXPECT_NEAR(splat_worst[k], splat_worst[0], 0.01);
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

// A splat file's fields come from the neighbouring splats: splats on the unit sphere with their true
// normals (as a splat file of a smooth object holds them) follow the sphere between the centres;
// on two faces of a cube no field bends across the edge; too few splats stay flat.
TEST(NormalField, FromNeighbouringSplatsFollowsTheSphereAndKeepsEdges) {
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss;
  std::vector<SplatRecord> sphere;
  for (int i = 0; i < 2000; ++i) {
    const DVec3 d = normalized(DVec3(gauss(rng), gauss(rng), gauss(rng)));
    const DVec3 u = any_perpendicular(d), v = cross(d, u);
    SplatRecord s;
    s.center = to_float(d), s.normal = to_float(d), s.major = to_float(0.08 * u), s.minor = to_float(0.06 * v);
    sphere.push_back(s);
  }
  NormalFieldStats stats;
  const std::vector<NormalField> fields = fit_normal_fields_from_splats(sphere, 60.0f, &stats);
  EXPECT_GE(stats.fitted, sphere.size() * 99 / 100);
  double field_sum = 0, flat_sum = 0;
  std::size_t points = 0;
  for (std::size_t i = 0; i < sphere.size(); ++i)
    for (const auto& [x, y] : {std::pair{0.8, 0.0}, {-0.8, 0.0}, {0.0, 0.8}, {0.0, -0.8}}) {
      const DVec3 p = DVec3(sphere[i].center) + x * DVec3(sphere[i].major) + y * DVec3(sphere[i].minor);
      field_sum += angle_degrees(field_normal(fields[i], x, y), normalized(p));
      flat_sum += angle_degrees(DVec3(sphere[i].normal), normalized(p));
      ++points;
    }
  std::printf("splats on the unit sphere: mean angle to the true normal %.2f° (flat %.2f°)\n", field_sum / static_cast<double>(points),
              flat_sum / static_cast<double>(points));
  EXPECT_LT(field_sum, 0.25 * flat_sum);

  std::vector<SplatRecord> faces;  // a grid on the cube's top face (z = 1) and on its side y = 1
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b) {
      SplatRecord top, side;
      const float s = 0.05f + 0.1f * static_cast<float>(a), t = 0.05f + 0.1f * static_cast<float>(b);
      top.center = {s, t, 1.0f}, top.normal = {0, 0, 1}, top.major = {0.07f, 0, 0}, top.minor = {0, 0.07f, 0};
      side.center = {s, 1.0f, t}, side.normal = {0, -1, 0}, side.major = {0.07f, 0, 0}, side.minor = {0, 0, 0.07f};  // inward: turned
      faces.push_back(top), faces.push_back(side);
    }
  const std::vector<NormalField> face_fields = fit_normal_fields_from_splats(faces, 60.0f);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, -1.0}})
      EXPECT_LT(angle_degrees(field_normal(face_fields[i], x, y), DVec3(faces[i].normal)), 1e-3) << "splat " << i;

  EXPECT_TRUE(fit_normal_fields_from_splats({}, 60.0f).empty());
  NormalFieldStats few;
  const auto pair = fit_normal_fields_from_splats({sphere[0], sphere[1]}, 60.0f, &few);
  EXPECT_EQ(few.flat, 2u);
  EXPECT_EQ(pair[0].centre, sphere[0].normal);
}

// Larger splats over a splat file's splats (its LOD tree's nodes): 40 tangent discs of radius 0.35
// on the unit sphere, fitted from 2,000 splats with the true normals, follow the sphere across
// them (the flat disc is off by up to its angular radius, ~20°, at its rim); over a cube's top face
// a node stays flat.
TEST(NormalField, NodesOverSplatsFollowTheSplats) {
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss;
  const auto tangent_splat = [](DVec3 d, double a, double b) {
    const DVec3 u = any_perpendicular(d), v = cross(d, u);
    SplatRecord s;
    s.center = to_float(d), s.normal = to_float(d), s.major = to_float(a * u), s.minor = to_float(b * v);
    return s;
  };
  std::vector<SplatRecord> sphere, nodes;
  for (int i = 0; i < 2000; ++i) sphere.push_back(tangent_splat(normalized(DVec3(gauss(rng), gauss(rng), gauss(rng))), 0.08, 0.06));
  for (int i = 0; i < 40; ++i) nodes.push_back(tangent_splat(normalized(DVec3(gauss(rng), gauss(rng), gauss(rng))), 0.35, 0.3));
  NormalFieldStats stats;
  const std::vector<NormalField> fields = fit_normal_fields_from_splats(nodes, sphere, 60.0f, &stats);
  ASSERT_EQ(fields.size(), nodes.size());
  EXPECT_EQ(stats.fitted, nodes.size());
  double field_sum = 0, flat_sum = 0;
  std::size_t points = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (const auto& [x, y] : {std::pair{0.9, 0.0}, {-0.9, 0.0}, {0.0, 0.9}, {0.0, -0.9}, {0.6, 0.6}}) {
      const DVec3 p = DVec3(nodes[i].center) + x * DVec3(nodes[i].major) + y * DVec3(nodes[i].minor);
      field_sum += angle_degrees(field_normal(fields[i], x, y), normalized(p));
      flat_sum += angle_degrees(DVec3(nodes[i].normal), normalized(p));
      ++points;
    }
  std::printf("nodes over splats on the unit sphere: mean angle to the true normal %.2f° (flat %.2f°)\n",
              field_sum / static_cast<double>(points), flat_sum / static_cast<double>(points));
  EXPECT_LT(field_sum, 0.2 * flat_sum);

  std::vector<SplatRecord> top;  // a grid on a cube's top face, and a node over it
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b) {
      SplatRecord s;
      s.center = {0.05f + 0.1f * static_cast<float>(a), 0.05f + 0.1f * static_cast<float>(b), 1.0f};
      s.normal = {0, 0, 1}, s.major = {0.07f, 0, 0}, s.minor = {0, 0.07f, 0};
      top.push_back(s);
    }
  SplatRecord node;
  node.center = {0.5f, 0.5f, 1.0f}, node.normal = {0, 0, 1}, node.major = {0.4f, 0, 0}, node.minor = {0, 0.4f, 0};
  const NormalField flat = fit_normal_fields_from_splats({node}, top, 60.0f)[0];
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, -1.0}})
    EXPECT_LT(angle_degrees(field_normal(flat, x, y), DVec3(0, 0, 1)), 1e-3);
  EXPECT_TRUE(fit_normal_fields_from_splats({}, top, 60.0f).empty());
  NormalFieldStats none;
  EXPECT_EQ(fit_normal_fields_from_splats({node}, {}, 60.0f, &none)[0].centre, node.normal);
  EXPECT_EQ(none.flat, 1u);
}

}  // namespace
}  // namespace splatcl::splats
