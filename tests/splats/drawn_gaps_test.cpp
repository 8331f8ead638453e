// cover_drawn_gaps after clip_to_surface, on the thesis's splats of meshes where they leave gaps: a
// low-poly sphere (its splats span several 30° facets), a cube (sharp edges and corners) and the
// creased part, at unit size and scaled by 1e-4 and 1e4; an inside-out cube, non-planar quads and a
// fan of slivers. Checked independently of the gap search
// (which subdivides triangles and relies on convexity): points drawn at random on the mesh, each
// must lie within the tolerance of a splat (its own ellipse and clip-line test here) that contains
// its projection and faces its way; and each gap splat, drawn at the splat scale k, must lie within
// the tolerance of the mesh at points of its rim and interior (brute-force distance to every triangle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "splats/pipeline.hpp"
#include "splats/surface.hpp"
#include "splats/surface_fit.hpp"
#include "splats_test_support.hpp"

namespace splatcl::splats {
namespace {

using namespace testing;

constexpr double kScale = 1.05;  // the presenter's default splat scale k

std::vector<SplatRecord> thesis_splats(const Mesh& mesh, double eps) {
  PipelineOptions options;
  options.fit.eps = static_cast<float>(eps);
  options.sampling = parse_sampling("grid:1.5");
  options.sampling.crease_degrees = options.fit.crease_degrees = 60.0f;  // the presenter's default crease angle
  return generate_splats(mesh, ColorSource{}, options, &runtime()).records();
}

Mesh scaled(Mesh mesh, float factor) {
  for (Vec3& v : mesh.vertices) v = {v.x * factor, v.y * factor, v.z * factor};
  return mesh;
}

struct Triangle {
  DVec3 a, b, c, normal;
  double area;
};
std::vector<Triangle> triangles_of(const Mesh& mesh) {
  std::vector<Triangle> out;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (std::uint32_t c = mesh.face_offsets[f] + 1; c + 1 < mesh.face_offsets[f + 1]; ++c) {
      Triangle t{DVec3(mesh.vertices[mesh.corners[mesh.face_offsets[f]]]), DVec3(mesh.vertices[mesh.corners[c]]),
                 DVec3(mesh.vertices[mesh.corners[c + 1]]), {}, 0};
      const DVec3 n = cross(t.b - t.a, t.c - t.a);
      t.area = 0.5 * length(n);
      if (!(t.area > 0)) continue;
      t.normal = normalized(n);
      out.push_back(t);
    }
  return out;
}

// Whether splat s (at its own size, both clip lines) holds p's projection, within `tolerance` in
// height, facing the way of `normal`.
bool holds(const SplatRecord& s, const ClipLine& second, DVec3 p, DVec3 normal, double tolerance) {
  const DVec3 c(s.center), major(s.major), minor(s.minor);
  const DVec3 n = normalized(cross(major, minor));
  const double a = length(major), b = length(minor);
  if (!(a > 0 && b > 0) || dot(DVec3(s.normal), normal) <= 0) return false;
  const DVec3 w = p - c;
  if (std::fabs(dot(w, n)) > tolerance) return false;
  const double x = dot(w, major) / a, y = dot(w, minor) / b;
  if (x * x / (a * a) + y * y / (b * b) > 1) return false;
  if (std::isfinite(s.clip_offset) && x * s.clip_x + y * s.clip_y > s.clip_offset) return false;
  return !std::isfinite(second.offset) || x * second.x + y * second.y <= second.offset;
}

double distance_to_mesh(const std::vector<Triangle>& triangles, DVec3 p) {
  double best = INFINITY;
  for (const Triangle& t : triangles) {
    // The closest point of the triangle (Ericson, Real-Time Collision Detection, 5.1.5).
    const DVec3 ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    DVec3 q;
    if (d1 <= 0 && d2 <= 0) {
      q = t.a;
    } else {
      const DVec3 bp = p - t.b;
      const double d3 = dot(ab, bp), d4 = dot(ac, bp);
      const DVec3 cp = p - t.c;
      const double d5 = dot(ab, cp), d6 = dot(ac, cp);
      const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
      if (d3 >= 0 && d4 <= d3) q = t.b;
      else if (d6 >= 0 && d5 <= d6) q = t.c;
      else if (vc <= 0 && d1 >= 0 && d3 <= 0) q = t.a + (d1 / (d1 - d3)) * ab;
      else if (vb <= 0 && d2 >= 0 && d6 <= 0) q = t.a + (d2 / (d2 - d6)) * ac;
      else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) q = t.b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (t.c - t.b);
      else {
        const double denom = 1 / (va + vb + vc);
        q = t.a + (vb * denom) * ab + (vc * denom) * ac;
      }
    }
    best = std::min(best, length(p - q));
  }
  return best;
}

struct Case {
  const char* name;
  Mesh mesh;
};

TEST(DrawnGaps, GapSplatsCoverTheSurfaceAsDrawn) {
  // The first three also at 1e-4 and 1e4 times their size.
  const Case cases[] = {{"low-poly sphere", sphere_mesh(6, 12, 1.2f)},
                        {"cube", cube_mesh()},
                        {"creased part", creased_part_mesh()},
                        {"inside-out cube", inside_out_cube_mesh()},
                        {"non-planar quads", non_planar_quads_mesh(6, 0.2f)},
                        {"sliver fan", sliver_fan_mesh(24)}};
  for (const Case& c : cases) {
    std::size_t gap_counts[3] = {};
    int run = 0;
    const bool scaled_too = &c - cases < 3;
    for (const float factor : {1.0f, 1e-4f, 1e4f}) {
      if (factor != 1.0f && !scaled_too) continue;
      const Mesh mesh = scaled(c.mesh, factor);
      const double diagonal = mesh.bounds().diagonal();
      const double eps = 0.00025 * diagonal, tolerance = 0.0025 * diagonal;  // the default scene's ε and surface_clip
      const std::string what = std::string(c.name) + " ×" + std::to_string(factor);
      const Surface surface(mesh);
      std::vector<SplatRecord> splats = thesis_splats(mesh, eps);
      std::vector<ClipLine> second;
      clip_to_surface(surface, splats, tolerance, kScale, second);
      SurfaceFitStats stats;
      std::vector<SplatRecord> gaps = cover_drawn_gaps(surface, splats, second, tolerance, kScale, stats);
      gap_counts[run++] = gaps.size();
      EXPECT_EQ(stats.uncovered_cells, 0u) << what;
      const std::vector<Triangle> triangles = triangles_of(mesh);
      // Each gap splat drawn at k stays within the tolerance of the mesh (1 % for the float rounding
      // of the stored splat).
      for (const SplatRecord& g : gaps) {
        const DVec3 centre(g.center), major(g.major), minor(g.minor);
        for (int k = 0; k < 16; ++k)
          for (const double r : {0.5, 1.0}) {
            const double angle = 2 * std::numbers::pi * k / 16;
            const DVec3 p = centre + (kScale * r * std::cos(angle)) * major + (kScale * r * std::sin(angle)) * minor;
            ASSERT_LE(distance_to_mesh(triangles, p), 1.01 * tolerance) << what;
          }
      }
      std::vector<SplatRecord> drawn = splats;
      std::vector<ClipLine> gap_second;
      clip_to_surface(surface, gaps, tolerance, kScale, gap_second);
      drawn.insert(drawn.end(), gaps.begin(), gaps.end());
      second.insert(second.end(), gap_second.begin(), gap_second.end());
      // Random points on the surface, by area; without the gap splats some are uncovered.
      double total = 0;
      for (const Triangle& t : triangles) total += t.area;
      std::mt19937_64 rng(7);
      std::uniform_real_distribution<double> unit(0, 1);
      std::size_t uncovered = 0, uncovered_without_gaps = 0;
      constexpr int kPoints = 4000;
      for (int i = 0; i < kPoints; ++i) {
        double pick = unit(rng) * total;
        const Triangle* t = &triangles.back();
        for (const Triangle& candidate : triangles)
          if ((pick -= candidate.area) <= 0) {
            t = &candidate;
            break;
          }
        double u = unit(rng), v = unit(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const DVec3 p = t->a + u * (t->b - t->a) + v * (t->c - t->a);
        const auto covered = [&](std::size_t count) {
          for (std::size_t j = 0; j < count; ++j)
            if (holds(drawn[j], second[j], p, t->normal, tolerance)) return true;
          return false;
        };
        uncovered += !covered(drawn.size());
        uncovered_without_gaps += !covered(splats.size());
      }
      EXPECT_EQ(uncovered, 0u) << what;
      if (factor == 1.0f)
        std::printf("%-16s %zu splats, %zu gap splats in %zu rounds; uncovered points of %d: %zu without them, %zu with\n", c.name,
                    splats.size(), gaps.size(), stats.gap_rounds, kPoints, uncovered_without_gaps, uncovered);
      if (std::string(c.name) == "low-poly sphere") {
        EXPECT_GT(uncovered_without_gaps, kPoints / 20) << what << ": the gaps this test guards";
      }
    }
    if (!scaled_too) continue;
    // The same fit at any scale (coordinates are relative to the mesh's size throughout).
    const double count = static_cast<double>(gap_counts[0]);
    EXPECT_NEAR(static_cast<double>(gap_counts[1]), count, 0.05 * count + 2) << c.name;
    EXPECT_NEAR(static_cast<double>(gap_counts[2]), count, 0.05 * count + 2) << c.name;
  }
}

// A gap splat takes the colour of the nearest same-facing splat nearby, else of the nearest one:
// on a thin shell whose top sheet alone carries (red) splats, the gap splats on its top take the
// top's colour and those on the bottom sheet, facing down, with no same-facing splat anywhere, the
// red of the splats just above them rather than a grey.
TEST(DrawnGaps, GapSplatsTakeTheNearestSplatsColour) {
  const Mesh mesh = thin_shell_mesh(0.01f);
  const Surface surface(mesh);
  std::vector<SplatRecord> top;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      SplatRecord s;
      s.center = {0.125f + 0.25f * static_cast<float>(a), 0.125f + 0.25f * static_cast<float>(b), 0.01f};
      s.normal = {0, 0, 1}, s.major = {0.1f, 0, 0}, s.minor = {0, 0.1f, 0};  // gaps between them
      s.color = {200, 10, 10, 255};
      top.push_back(s);
    }
  SurfaceFitStats stats;
  const std::vector<SplatRecord> gaps = cover_drawn_gaps(surface, top, {}, 0.002, 1.05, stats);
  EXPECT_EQ(stats.uncovered_cells, 0u);
  std::size_t up = 0, down = 0;
  for (const SplatRecord& g : gaps) {
    if (g.normal.z > 0.9f) ++up;
    if (g.normal.z < -0.9f) ++down;
    if (std::fabs(g.normal.z) > 0.9f) {
      EXPECT_EQ(g.color, (Rgba8{200, 10, 10, 255}));
    }
  }
  EXPECT_GT(up, 0u);
  EXPECT_GT(down, 0u);
}

}  // namespace
}  // namespace splatcl::splats
