#include "splats/normal_field.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <cmath>
#include <numbers>

#include "core/parallel.hpp"
#include "math/dvec3.hpp"
#include "splats/neighbors.hpp"
#include "splats/sampling.hpp"

namespace splatcl::splats {
namespace {

// The fit's points in ellipse coordinates: the centre, 6 at radius 0.45 and 12 at 0.9.
constexpr std::size_t kInnerPoints = 6, kOuterPoints = 12, kPoints = 1 + kInnerPoints + kOuterPoints;
// Fewer kept points than this leave the splat flat: a line of points cannot fix two gradients.
constexpr std::size_t kMinPoints = 6;
// Splat files: the nearest splats, those whose centres lie within this many major semi-axes, with
// the splat's own normal at its centre; at least this many points in all.
constexpr unsigned kSplatNeighbours = 12;
constexpr double kSplatReach = 2.0;
constexpr std::size_t kMinSplatPoints = 4;
// A larger splat (an LOD tree node) over many splats: its field from this many nearest of them.
constexpr std::size_t kTargetNeighbours = 64;

std::array<std::array<double, 2>, kPoints> fit_points() {
  std::array<std::array<double, 2>, kPoints> points{};
  std::size_t i = 1;
  for (std::size_t k = 0; k < kInnerPoints; ++k, ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / kInnerPoints;
    points[i] = {0.45 * std::cos(a), 0.45 * std::sin(a)};
  }
  for (std::size_t k = 0; k < kOuterPoints; ++k, ++i) {
    const double a = 2.0 * std::numbers::pi * (static_cast<double>(k) + 0.5) / kOuterPoints;
    points[i] = {0.9 * std::cos(a), 0.9 * std::sin(a)};
  }
  return points;
}

// The smooth normal at q, the closest point of triangle t: its corners' normals interpolated by
// barycentric weights (the face normal where they cancel).
DVec3 smooth_normal(const SurfaceTriangle& t, const std::vector<Vec3>& corner_normal, DVec3 q) {
  const Barycentric w = barycentric(t, q);
  const DVec3 s = w.a * DVec3(corner_normal[t.corners[0]]) + w.b * DVec3(corner_normal[t.corners[1]]) +
                  w.c * DVec3(corner_normal[t.corners[2]]);
  return length(s) > 0 ? normalized(s) : t.normal;
}

bool kept_by(float x, float y, float offset, double px, double py) { return !(px * x + py * y > offset); }

// Solves the 3 × 3 symmetric system m · r = b (Cramer's rule); false when it is singular.
bool solve3(const double m[3][3], const double b[3], double r[3]) {
  const auto det = [](double a00, double a01, double a02, double a10, double a11, double a12, double a20, double a21, double a22) {
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20);
  };
  const double d = det(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  if (!(std::fabs(d) > 1e-9)) return false;
  r[0] = det(b[0], m[0][1], m[0][2], b[1], m[1][1], m[1][2], b[2], m[2][1], m[2][2]) / d;
  r[1] = det(m[0][0], b[0], m[0][2], m[1][0], b[1], m[1][2], m[2][0], b[2], m[2][2]) / d;
  r[2] = det(m[0][0], m[0][1], b[0], m[1][0], m[1][1], b[1], m[2][0], m[2][1], b[2]) / d;
  return true;
}

// Least squares of n(x, y) = centre + x·du + y·dv over unit normals at ellipse coordinates (x, y),
// one 3 × 3 system shared by the three components.
class FieldFit {
 public:
  void add(double x, double y, DVec3 normal) {
    const double row[3] = {1.0, x, y};
    const double value[3] = {normal.x, normal.y, normal.z};
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) m_[r][k] += row[r] * row[k];
      for (int comp = 0; comp < 3; ++comp) b_[comp][r] += row[r] * value[comp];
    }
    ++points_;
  }
  std::size_t points() const { return points_; }
  // The field, unless it is singular (the points on a line) or turns more than the crease angle
  // away from the splat's normal n at its centre (a fit over a fold).
  bool solve(DVec3 n, double cos_crease, NormalField& field) const {
    double r[3][3];  // r[component] = (centre, du, dv) of that component
    for (int comp = 0; comp < 3; ++comp)
      if (!solve3(m_, b_[comp], r[comp])) return false;
    const Vec3 centre = to_float({r[0][0], r[1][0], r[2][0]}), du = to_float({r[0][1], r[1][1], r[2][1]}),
               dv = to_float({r[0][2], r[1][2], r[2][2]});
    if (!finite(centre) || !finite(du) || !finite(dv) || !(dot(DVec3(centre), n) > cos_crease * length(DVec3(centre)))) return false;
    field = {centre, du, dv};
    return true;
  }

 private:
  double m_[3][3] = {}, b_[3][3] = {};  // b_[component][row]
  std::size_t points_ = 0;
};

// Counts the fitted fields into stats.
void count(const std::vector<unsigned char>& fitted, NormalFieldStats* stats) {
  if (!stats) return;
  stats->fitted = 0;
  for (const unsigned char f : fitted) stats->fitted += f;
  stats->flat = fitted.size() - stats->fitted;
}

}  // namespace

std::vector<NormalField> fit_normal_fields(const Mesh& mesh, const Surface& surface, const std::vector<SplatRecord>& splats,
                                           const std::vector<ClipLine>& second_lines, float crease_degrees,
                                           NormalFieldStats* stats) {
  const std::vector<Vec3> corner_normal = corner_normals(mesh, crease_degrees);
  const double cos_crease = std::cos(static_cast<double>(crease_degrees) * std::numbers::pi / 180.0);
  const auto points = fit_points();
  std::vector<NormalField> fields(splats.size());
  std::vector<unsigned char> fitted(splats.size(), 0);
  parallel_for(splats.size(), 64, [&](std::size_t i, std::size_t) {
    const SplatRecord& s = splats[i];
    NormalField& field = fields[i];
    field = {s.normal, {}, {}};
    const DVec3 c(s.center), major(s.major), minor(s.minor), n = normalized(DVec3(s.normal));
    const double la = length(major), lb = length(minor);
    if (!(la > 0 && lb > 0) || !(length(n) > 0)) return;
    const DVec3 ua = (1.0 / la) * major, ub = (1.0 / lb) * minor;
    const double limit = lb + 0.25 * la;
    const ClipLine second = i < second_lines.size() ? second_lines[i] : ClipLine{};
    FieldFit fit;
    Surface::Recent recent;
    for (const auto& [px, py] : points) {
      if (!kept_by(s.clip_x, s.clip_y, s.clip_offset, px * la, py * lb) || !kept_by(second.x, second.y, second.offset, px * la, py * lb))
        continue;
      const DVec3 p = c + (px * la) * ua + (py * lb) * ub;
      const Surface::Nearest near = surface.nearest(p, limit, &recent);
      if (near.triangle == UINT32_MAX) continue;
      const SurfaceTriangle& t = surface.triangles()[near.triangle];
      const DVec3 q = closest_point(t, p);
      DVec3 normal = smooth_normal(t, corner_normal, q);
      if (dot(normal, n) < 0) normal = -1.0 * normal;
      if (dot(normal, n) < cos_crease) continue;
      fit.add(dot(q - c, ua) / la, dot(q - c, ub) / lb, normal);
    }
    if (fit.points() >= kMinPoints && fit.solve(n, cos_crease, field)) fitted[i] = 1;
  });
  count(fitted, stats);
  return fields;
}

namespace {

// The field of splat s from the normals of `neighbours` (nearest first, s itself left out), at their
// centres' ellipse coordinates; false (s stays flat) with too few of them on its side.
template <class Neighbours>
bool fit_from_neighbours(const SplatRecord& s, const Neighbours& neighbours, double cos_crease, NormalField& field) {
  const DVec3 c(s.center), major(s.major), minor(s.minor), n = normalized(DVec3(s.normal));
  const double la = length(major), lb = length(minor);
  if (!(la > 0 && lb > 0) || !(length(n) > 0)) return false;
  const DVec3 ua = (1.0 / la) * major, ub = (1.0 / lb) * minor;
  FieldFit fit;
  fit.add(0.0, 0.0, n);
  for (const SplatRecord* other : neighbours) {
    const DVec3 d = DVec3(other->center) - c;
    if (length(d) > kSplatReach * la) break;  // nearest first
    DVec3 normal = normalized(DVec3(other->normal));
    if (dot(normal, n) < 0) normal = -1.0 * normal;
    if (dot(normal, n) < cos_crease || std::fabs(dot(d, n)) > la) continue;  // across a crease, or another sheet
    fit.add(dot(d, ua) / la, dot(d, ub) / lb, normal);
  }
  return fit.points() >= kMinSplatPoints && fit.solve(n, cos_crease, field);
}

double cosine_of(float degrees) { return std::cos(static_cast<double>(degrees) * std::numbers::pi / 180.0); }

std::vector<NormalField> flat_fields(const std::vector<SplatRecord>& splats) {
  std::vector<NormalField> fields(splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) fields[i] = {splats[i].normal, {}, {}};
  return fields;
}

}  // namespace

std::vector<NormalField> fit_normal_fields_from_splats(const std::vector<SplatRecord>& splats, float crease_degrees,
                                                       NormalFieldStats* stats) {
  const double cos_crease = cosine_of(crease_degrees);
  std::vector<NormalField> fields = flat_fields(splats);
  std::vector<unsigned char> fitted(splats.size(), 0);
  if (splats.size() < 2) {
    count(fitted, stats);
    return fields;
  }
  std::vector<Vec4> centres(splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) centres[i] = to_vec4(splats[i].center);
  const Neighborhoods near = find_neighbors(centres, kSplatNeighbours);
  parallel_for(splats.size(), 256, [&](std::size_t i, std::size_t) {
    std::array<const SplatRecord*, kSplatNeighbours> neighbours{};
    for (std::uint32_t k = 0; k < near.k; ++k) neighbours[k] = &splats[near.row(i)[k]];  // rows are sorted by distance
    const std::span<const SplatRecord* const> row(neighbours.data(), near.k);
    fitted[i] = fit_from_neighbours(splats[i], row, cos_crease, fields[i]);
  });
  count(fitted, stats);
  return fields;
}

std::vector<NormalField> fit_normal_fields_from_splats(const std::vector<SplatRecord>& targets, const std::vector<SplatRecord>& splats,
                                                       float crease_degrees, NormalFieldStats* stats) {
  const double cos_crease = cosine_of(crease_degrees);
  std::vector<NormalField> fields = flat_fields(targets);
  std::vector<unsigned char> fitted(targets.size(), 0);
  std::vector<BoxTree::Box> boxes(splats.size());
  for (std::size_t j = 0; j < splats.size(); ++j) boxes[j].add(DVec3(splats[j].center));
  const BoxTree tree(boxes);
  parallel_for(targets.size(), 16, [&](std::size_t i, std::size_t) {
    const SplatRecord& t = targets[i];
    // The splats whose centres lie within the reach, the nearest kTargetNeighbours of them.
    std::vector<std::pair<double, std::uint32_t>> found;
    double reach = kSplatReach * length(DVec3(t.major));
    const DVec3 c(t.center);
    tree.visit(c, reach, [&](std::uint32_t j, double&) {
      found.push_back({length(DVec3(splats[j].center) - c), j});
      return false;
    });
    const std::size_t keep = std::min(found.size(), kTargetNeighbours);
    std::partial_sort(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(keep), found.end());
    std::vector<const SplatRecord*> neighbours(keep);
    for (std::size_t k = 0; k < keep; ++k) neighbours[k] = &splats[found[k].second];
    fitted[i] = fit_from_neighbours(t, neighbours, cos_crease, fields[i]);
  });
  count(fitted, stats);
  return fields;
}

}  // namespace splatcl::splats
