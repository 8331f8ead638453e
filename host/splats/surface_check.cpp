#include "splats/surface_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "math/dvec3.hpp"
#include "runtime/error.hpp"
#include "core/parallel.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/surface.hpp"

namespace splatcl::splats {
namespace {

constexpr std::uint64_t kSurfaceSalt = 0x5bd1e9955bd1e995ULL, kSplatSalt = 0xc2b2ae3d27d4eb4fULL;
// The flipped count's search radius, max(ε, the nearest triangle's distance), grows by this (× ε)
// for ties at edges and vertices.
constexpr double kFlipTieSlack = 1e-3;

// The `stream`-th output of a SplitMix64 stream keyed by seed and salt: independent, reproducible
// seeds for chunks and splats, whatever the thread count.
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t salt, std::uint64_t stream) {
  SplitMix64 m{(seed ^ salt) + stream * 0x9e3779b97f4a7c15ULL};
  return m.next();
}

// A splat in double with the ellipse frame made unit; valid == false for a degenerate one.
struct CheckedEllipse {
  DVec3 c, u, v, n;
  double a = 0, b = 0;
  bool clipped = false;
  double cx = 0, cy = 0, off = INFINITY;
  // The clip in the unit-disk frame (X, Y) = (x / a, y / b): kept where (X, Y)·w <= d, |w| = 1.
  double wx = 1, wy = 0, d = 1;
  double area = 0;  // of the kept part
  bool valid = false;
};

bool finite3(Vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

CheckedEllipse prepare(const SplatRecord& s) {
  CheckedEllipse e;
  if (!finite3(s.center) || !finite3(s.normal) || !finite3(s.major) || !finite3(s.minor) || !std::isfinite(s.clip_x) ||
      !std::isfinite(s.clip_y) || std::isnan(s.clip_offset))
    return e;
  e.c = DVec3(s.center);
  const DVec3 major(s.major), minor(s.minor), normal(s.normal);
  e.a = length(major), e.b = length(minor);
  const double nl = length(normal);
  if (!(e.a > 0 && e.b > 0 && nl > 0) || !std::isfinite(e.a) || !std::isfinite(e.b) || !std::isfinite(nl)) return e;
  e.u = (1 / e.a) * major, e.v = (1 / e.b) * minor, e.n = (1 / nl) * normal;
  e.area = std::numbers::pi * e.a * e.b;
  if (s.clip_offset < INFINITY) {
    e.cx = s.clip_x, e.cy = s.clip_y, e.off = s.clip_offset;
    // x cx + y cy <= off  ⇔  X (a cx) + Y (b cy) <= off.
    const double wx = e.a * e.cx, wy = e.b * e.cy, w = std::hypot(wx, wy);
    if (!(w > 0)) {
      if (!(e.off >= 0)) return e;  // a zero direction keeps all or nothing
    } else {
      e.wx = wx / w, e.wy = wy / w, e.d = e.off / w;
      if (!(e.d > -1)) return e;  // nothing kept
      if (e.d < 1) {
        e.clipped = true;
        // The unit disk's part with t <= d: π minus the cap acos(d) − d √(1 − d²).
        e.area = e.a * e.b * (std::numbers::pi - std::acos(e.d) + e.d * std::sqrt(1 - e.d * e.d));
      }
    }
  }
  e.valid = true;
  return e;
}

DVec3 at(const CheckedEllipse& e, double x, double y) { return e.c + x * e.u + y * e.v; }

// ceil(x) clamped to [lo, hi], for any x (huge, infinite or NaN included).
std::size_t clamped_count(double x, std::size_t lo, std::size_t hi) {
  const double c = std::ceil(x);
  if (!(c > static_cast<double>(lo))) return lo;
  return c >= static_cast<double>(hi) ? hi : static_cast<std::size_t>(c);
}

// The points checked on one splat: `interior` area-uniform points over the kept part (rejection
// sampling in the kept part's bounding box in the clip frame of the unit disk, mapped to the
// ellipse), then the rim (at least 32 points, at most ε apart along it, at most 512) on the kept
// side, then the clip chord (at least 16 points, at most ε apart, at most 512).
struct SplatPoints {
  std::vector<DVec3> points;
  std::size_t interior = 0, rim_end = 0;  // points [0, interior) interior, [interior, rim_end) rim, then the chord
  std::vector<double> rim_angles;          // of the rim points
  double rim_step = 0;
};

DVec3 rim_point(const CheckedEllipse& e, double angle) { return at(e, e.a * std::cos(angle), e.b * std::sin(angle)); }
bool kept(const CheckedEllipse& e, double angle) { return !e.clipped || std::cos(angle) * e.wx + std::sin(angle) * e.wy <= e.d; }

void splat_points(const CheckedEllipse& e, std::size_t index, const SurfaceCheckOptions& options, SplatPoints& out) {
  out.points.clear();
  out.rim_angles.clear();
  SplitMix64 random{stream_seed(options.seed, kSplatSalt, index)};
  const double d = std::min(e.d, 1.0);
  const double half = d >= 0 ? 1.0 : std::sqrt(std::max(0.0, 1 - d * d));  // of the kept part across w
  const double px = -e.wy, py = e.wx;  // the chord direction
  for (std::size_t tries = 0; out.points.size() < options.ellipse_points && tries < 100 * options.ellipse_points; ++tries) {
    const double t = -1 + (d + 1) * random.uniform(), s = half * (2 * random.uniform() - 1);
    if (t * t + s * s > 1 || t > d) continue;
    out.points.push_back(at(e, e.a * (t * e.wx + s * px), e.b * (t * e.wy + s * py)));
  }
  out.interior = out.points.size();
  const std::size_t rim = clamped_count(2 * std::numbers::pi * e.a / options.eps, 32, 512);
  out.rim_step = 2 * std::numbers::pi / static_cast<double>(rim);
  for (std::size_t k = 0; k < rim; ++k) {
    const double angle = out.rim_step * static_cast<double>(k);
    if (!kept(e, angle)) continue;
    out.points.push_back(rim_point(e, angle));
    out.rim_angles.push_back(angle);
  }
  out.rim_end = out.points.size();
  if (e.clipped) {
    const double h = std::sqrt(std::max(0.0, 1 - d * d));
    const double chord = 2 * h * std::hypot(e.a * px, e.b * py);
    const std::size_t count = clamped_count(chord / options.eps + 1, 16, 512);
    for (std::size_t k = 0; k < count; ++k) {
      const double s = -h + 2 * h * static_cast<double>(k) / static_cast<double>(count - 1);
      out.points.push_back(at(e, e.a * (d * e.wx + s * px), e.b * (d * e.wy + s * py)));
    }
  }
}

struct SplatResult {
  double max_distance = 0;  // over the points within the limit
  bool past_limit = false;  // some point has no triangle within the limit
  DVec3 far_point;          // of those, the one farthest from the centre
  double beyond_share = 0;  // of the interior points beyond ε (1 + slack)
  bool beyond = false;
  std::size_t points = 0;
};

// Distances of one splat's points to the surface (nearest triangle within `limit`). The rim's
// farthest point is then refined along the rim (3 rounds of 8 points, each round 2/9 of the last
// one's spacing), since the distance of a flat splat to the surface peaks on its rim. A point only
// needs its distance when it may raise a maximum or lie beyond ε: one within the lower of the two
// (a cheaper query, which stops at the first triangle near enough) changes nothing, so the rim
// goes first and the interior then mostly takes that query.
SplatResult measure_splat(const CheckedEllipse& e, std::size_t index, const SurfaceCheckOptions& options, const Surface& surface, double limit,
                          SplatPoints& scratch) {
  SplatResult r;
  const double eps_slack = options.eps * (1 + options.slack);
  splat_points(e, index, options, scratch);
  double far = -1;
  std::size_t interior_beyond = 0, rim_best = SIZE_MAX;
  double rim_max = -1;
  Surface::Recent recent;
  // The distance of p, or -1 when p lies within `known` (>= 0) and so changes nothing.
  const auto measure = [&](DVec3 p, double known) {
    ++r.points;
    if (known >= 0 && surface.within(p, known, &recent)) return -1.0;
    const Surface::Nearest nearest = surface.nearest(p, limit, &recent);
    if (nearest.triangle == UINT32_MAX) {
      r.past_limit = r.beyond = true;
      if (const double l = length(p - e.c); l > far) far = l, r.far_point = p;
      return static_cast<double>(INFINITY);
    }
    r.max_distance = std::max(r.max_distance, nearest.distance);
    r.beyond = r.beyond || nearest.distance > eps_slack;
    return nearest.distance;
  };
  for (std::size_t k = scratch.interior; k < scratch.rim_end; ++k)
    if (const double distance = measure(scratch.points[k], std::min(rim_max, eps_slack)); distance > rim_max)
      rim_max = distance, rim_best = k - scratch.interior;
  for (std::size_t k = scratch.rim_end; k < scratch.points.size(); ++k) measure(scratch.points[k], std::min(r.max_distance, eps_slack));
  for (std::size_t k = 0; k < scratch.interior; ++k)
    if (!(measure(scratch.points[k], std::min(r.max_distance, eps_slack)) <= eps_slack)) ++interior_beyond;
  if (rim_best != SIZE_MAX && std::isfinite(rim_max)) {
    double angle = scratch.rim_angles[rim_best], step = scratch.rim_step;
    for (int round = 0; round < 3; ++round) {
      const double centre = angle;
      for (int k = -4; k <= 4; ++k) {
        if (k == 0) continue;
        const double a = centre + k * step * 2 / 9;
        if (!kept(e, a)) continue;
        if (const double distance = measure(rim_point(e, a), std::min(rim_max, eps_slack)); distance > rim_max) rim_max = distance, angle = a;
      }
      step *= 2.0 / 9;
    }
  }
  r.beyond_share = scratch.interior > 0 ? static_cast<double>(interior_beyond) / static_cast<double>(scratch.interior) : 0.0;
  return r;
}

// The axis-aligned box of the region where the ellipse covers a surface point: the ellipse grown
// by the slack, thickened by ε (1 + slack) along every axis.
BoxTree::Box coverage_box(const CheckedEllipse& e, double eps_slack, double slack) {
  const double grow = std::sqrt(1 + slack) * (1 + 1e-9);
  const auto extent = [&](double ux, double vx) { return grow * std::hypot(e.a * ux, e.b * vx) + eps_slack * (1 + 1e-9); };
  const DVec3 r{extent(e.u.x, e.v.x), extent(e.u.y, e.v.y), extent(e.u.z, e.v.z)};
  BoxTree::Box box;
  box.add(e.c - r);
  box.add(e.c + r);
  return box;
}

struct Uncovered {
  std::uint64_t index;  // of the surface point
  Vec3 position;
};

// Connected components of points linked within `link` (each point's root, and their count): a
// grid of cells of that size, each cell linked to itself and its 13 forward neighbours, union-find
// over the pairs.

std::vector<std::uint32_t> cluster(const std::vector<Uncovered>& points, double link, std::size_t& components) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  using Cell = std::array<std::int64_t, 3>;
  std::vector<Cell> cells(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = points[i].position;
    cells[i] = {static_cast<std::int64_t>(std::floor(p.x / link)), static_cast<std::int64_t>(std::floor(p.y / link)),
                static_cast<std::int64_t>(std::floor(p.z / link))};
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return cells[a] < cells[b] || (cells[a] == cells[b] && a < b); });
  // Unique cells with their ranges in `order`.
  std::vector<Cell> keys;
  std::vector<std::uint32_t> starts;
  for (std::uint32_t r = 0; r < n; ++r)
    if (r == 0 || cells[order[r]] != cells[order[r - 1]]) keys.push_back(cells[order[r]]), starts.push_back(r);
  starts.push_back(static_cast<std::uint32_t>(n));
  const double link2 = link * link;
  const auto close = [&](std::uint32_t i, std::uint32_t j) {
    const DVec3 d = DVec3(points[i].position) - DVec3(points[j].position);
    return dot(d, d) <= link2;
  };
  const auto unite = [&](std::uint32_t i, std::uint32_t j) {
    const std::uint32_t a = find(i), b = find(j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Cell c = keys[k];
    for (std::uint32_t r = starts[k]; r < starts[k + 1]; ++r)
      for (std::uint32_t q = r + 1; q < starts[k + 1]; ++q)
        if (close(order[r], order[q])) unite(order[r], order[q]);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Cell other{c[0] + dx, c[1] + dy, c[2] + dz};
          if (!(c < other)) continue;  // each unordered pair of cells once
          const auto it = std::lower_bound(keys.begin(), keys.end(), other);
          if (it == keys.end() || *it != other) continue;
          const std::size_t m = static_cast<std::size_t>(it - keys.begin());
          for (std::uint32_t r = starts[k]; r < starts[k + 1]; ++r)
            for (std::uint32_t q = starts[m]; q < starts[m + 1]; ++q)
              if (close(order[r], order[q])) unite(order[r], order[q]);
        }
  }
  components = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    parent[i] = find(i);
    if (parent[i] == i) ++components;
  }
  return parent;
}

// The largest distance between the points (a lower bound, tight in practice): the widest of 13
// directions, then two farthest-point sweeps from that direction's extreme.
double diameter(const std::vector<DVec3>& points) {
  if (points.size() < 2) return 0;
  static const double r2 = std::sqrt(0.5), r3 = std::sqrt(1.0 / 3);
  const DVec3 directions[13] = {{1, 0, 0},   {0, 1, 0},   {0, 0, 1},   {r2, r2, 0},  {r2, -r2, 0}, {r2, 0, r2},  {r2, 0, -r2},
                                {0, r2, r2}, {0, r2, -r2}, {r3, r3, r3}, {r3, r3, -r3}, {r3, -r3, r3}, {-r3, r3, r3}};
  double best = 0;
  std::size_t start = 0;
  for (const DVec3& w : directions) {
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 1; i < points.size(); ++i) {
      if (dot(points[i], w) < dot(points[lo], w)) lo = i;
      if (dot(points[i], w) > dot(points[hi], w)) hi = i;
    }
    const double width = dot(points[hi] - points[lo], w);
    if (width > best) best = width, start = hi;
  }
  for (int sweep = 0; sweep < 2; ++sweep) {
    std::size_t far = start;
    double distance = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (const double l = length(points[i] - points[start]); l > distance) distance = l, far = i;
    best = std::max(best, distance);
    start = far;
  }
  return best;
}

}  // namespace

double unclamped_surface_points(double area, double eps) { return 5 * area / (std::numbers::pi * eps * eps); }

std::size_t default_surface_points(double area, double eps) {
  const double n = std::ceil(unclamped_surface_points(area, eps));
  if (!(n >= static_cast<double>(kMinSurfacePoints))) return kMinSurfacePoints;  // NaN included
  if (n >= static_cast<double>(kMaxSurfacePoints)) return kMaxSurfacePoints;
  return static_cast<std::size_t>(n);
}

SurfaceCheckReport check_surface(const Mesh& mesh, const std::vector<SplatRecord>& splats, const SurfaceCheckOptions& options,
                                 const SurfaceCheckProgress& progress) {
  if (!(options.eps > 0) || !std::isfinite(options.eps)) throw Error("surface check: eps must be finite and positive");
  if (options.ellipse_points < 1) throw Error("surface check: at least one point per ellipse is needed");
  if (!(options.slack >= 0) || !std::isfinite(options.slack)) throw Error("surface check: the slack must be finite and non-negative");
  const auto report_progress = [&](const std::string& phase, double fraction) {
    if (progress) progress(phase, fraction);
  };
  report_progress("preparing the surface", 0);
  const Surface surface(mesh);
  if (!(surface.area() > 0)) throw Error("surface check: " + mesh.source + " has no surface area");
  SurfaceCheckReport report;
  report.eps = options.eps, report.slack = options.slack, report.seed = options.seed;
  report.surface_area = surface.area();
  report.splats = splats.size();
  {
    BoxTree::Box bounds;
    for (const SurfaceTriangle& t : surface.triangles()) bounds.add(t.a), bounds.add(t.b), bounds.add(t.c);
    report.diagonal = length(bounds.hi - bounds.lo);
  }
  const double eps = options.eps, slack = options.slack, eps_slack = eps * (1 + slack);

  std::vector<CheckedEllipse> ellipses(splats.size());
  std::vector<std::uint32_t> valid;  // coverage tree item → splat index
  std::vector<BoxTree::Box> boxes;
  for (std::size_t j = 0; j < splats.size(); ++j) {
    ellipses[j] = prepare(splats[j]);
    if (!ellipses[j].valid) {
      ++report.degenerate;
      continue;
    }
    report.largest_major = std::max(report.largest_major, ellipses[j].a);
    valid.push_back(static_cast<std::uint32_t>(j));
    boxes.push_back(coverage_box(ellipses[j], eps_slack, slack));
  }
  const BoxTree coverage(boxes);

  // (B) Surface points, generated and tested in sub-chunks seeded by their index (so the points
  // and the result do not depend on the thread count), a round of sub-chunks at a time.
  if (options.surface_points > 0) {
    report.surface_points = options.surface_points;
  } else {
    report.surface_points_wanted = unclamped_surface_points(surface.area(), eps);
    report.surface_points = default_surface_points(surface.area(), eps);
    report.surface_points_clamped = !(std::ceil(report.surface_points_wanted) == static_cast<double>(report.surface_points));
  }
  const std::size_t n = report.surface_points;
  constexpr std::size_t kChunk = 1 << 14, kRound = 64, kHoleCap = 2'000'000;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<Uncovered> uncovered;
  std::size_t thinning = 1;
  const auto covered = [&](const Surface::Point& p) {
    double radius = 0;
    bool found = false;
    coverage.visit(p.position, radius, [&](std::uint32_t item, double&) {
      const CheckedEllipse& e = ellipses[valid[item]];
      const DVec3 d = p.position - e.c;
      if (!(std::fabs(dot(e.n, d)) <= eps_slack)) return false;
      const double x = dot(e.u, d), y = dot(e.v, d);
      if (!(x * x / (e.a * e.a) + y * y / (e.b * e.b) <= 1 + slack)) return false;
      if (e.off < INFINITY && !(x * e.cx + y * e.cy <= e.off + slack * std::max(e.a, e.b))) return false;
      if (!(dot(e.n, p.normal) > 0)) return false;
      return found = true;
    });
    return found;
  };
  for (std::size_t first = 0; first < chunks; first += kRound) {
    report_progress("checking surface points", static_cast<double>(first) / static_cast<double>(chunks));
    const std::size_t count = std::min(kRound, chunks - first);
    std::vector<std::vector<Uncovered>> found(count);
    std::vector<std::size_t> misses(count, 0);
    parallel_for(count, 1, [&](std::size_t c, std::size_t) {
      const std::size_t chunk = first + c, begin = chunk * kChunk, size = std::min(kChunk, n - begin);
      const std::vector<Surface::Point> points = surface.uniform_points(size, stream_seed(options.seed, kSurfaceSalt, chunk));
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (covered(points[i])) continue;
        ++misses[c];
        if ((begin + i) % thinning == 0) found[c].push_back({begin + i, to_float(points[i].position)});
      }
    });
    for (std::size_t c = 0; c < count; ++c) {
      report.uncovered_points += misses[c];
      uncovered.insert(uncovered.end(), found[c].begin(), found[c].end());
    }
    // Keep memory bounded: past the cap, keep every (2k)-th point instead of every k-th.
    while (uncovered.size() > kHoleCap) {
      thinning *= 2;
      std::erase_if(uncovered, [&](const Uncovered& u) { return u.index % thinning != 0; });
    }
  }
  report.uncovered_fraction = n > 0 ? static_cast<double>(report.uncovered_points) / static_cast<double>(n) : 0.0;
  report.hole_thinning = thinning;
  if (!uncovered.empty()) {
    report_progress("clustering uncovered points", 0);
    const double kept = static_cast<double>(n) / static_cast<double>(thinning);  // the density the kept points have
    const double spacing = std::sqrt(surface.area() / kept);
    std::size_t components = 0;
    const std::vector<std::uint32_t> root = cluster(uncovered, 2.5 * spacing, components);
    report.holes = components;
    std::vector<std::uint32_t> sizes(uncovered.size(), 0);
    for (const std::uint32_t r : root) ++sizes[r];
    const std::uint32_t largest = static_cast<std::uint32_t>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
    std::vector<DVec3> hole;
    for (std::size_t i = 0; i < uncovered.size(); ++i)
      if (root[i] == largest) hole.push_back(DVec3(uncovered[i].position));
    report.largest_hole_points = hole.size() * thinning;
    report.largest_hole_area = static_cast<double>(hole.size()) * surface.area() / kept;
    report.largest_hole_diameter = diameter(hole);
  }

  // (A) Splat points: nearest triangle within 16 ε; points beyond that are checked without a
  // limit afterwards, for the splat that reaches farthest.
  const double limit = 16 * eps;
  std::vector<SplatResult> results(splats.size());
  std::vector<char> flipped(splats.size(), 0);
  constexpr std::size_t kSplatRound = 4096;
  std::vector<SplatPoints> scratch(worker_count(splats.size(), 16));
  for (std::size_t first = 0; first < splats.size(); first += kSplatRound) {
    report_progress("checking splats", static_cast<double>(first) / static_cast<double>(splats.size()));
    parallel_for(std::min(kSplatRound, splats.size() - first), 16, [&](std::size_t i, std::size_t worker) {
      const std::size_t j = first + i;
      const CheckedEllipse& e = ellipses[j];
      if (!e.valid) return;
      const Surface::Nearest centre = surface.nearest(e.c);
      // Flipped: no triangle within ε of the centre (or at its distance, if farther) faces the
      // splat's way within 60°. A splat may lie up to ε off its surface, and where another surface
      // facing the other way is nearer (two parts that touch or interpenetrate, a part thinner
      // than ε) the nearest triangle is that one's: the ogre's teeth in its gums were 562 flipped
      // splats that way. At an edge or vertex several triangles tie for nearest (the slack).
      if (centre.triangle != UINT32_MAX && dot(e.n, surface.triangles()[centre.triangle].normal) < 0) {
        const Surface::Facing same_way{e.n, kFacingCos, true};
        flipped[j] = !surface.within(e.c, std::max(centre.distance, eps) + kFlipTieSlack * eps, nullptr, &same_way);
      }
      results[j] = measure_splat(e, j, options, surface, limit, scratch[worker]);
    });
  }
  report_progress("checking splats", 1);
  double total_area = 0, beyond_area = 0;
  std::vector<std::uint32_t> past;
  for (std::size_t j = 0; j < splats.size(); ++j) {
    if (!ellipses[j].valid) continue;
    const SplatResult& r = results[j];
    report.splat_points += r.points;
    total_area += ellipses[j].area;
    beyond_area += ellipses[j].area * r.beyond_share;
    report.splats_beyond += r.beyond ? 1 : 0;
    report.flipped += flipped[j] ? 1 : 0;
    if (r.past_limit) past.push_back(static_cast<std::uint32_t>(j));
    if (r.max_distance > report.max_distance) report.max_distance = r.max_distance, report.worst_splat = j;
  }
  report.area_beyond_fraction = total_area > 0 ? beyond_area / total_area : 0.0;
  if (!past.empty()) {
    // Some points have no triangle within the limit: rank those splats by the true distance of
    // their point farthest from the centre, then measure the farthest one again without a limit.
    std::vector<double> far(past.size());
    parallel_for(past.size(), 4, [&](std::size_t i, std::size_t) { far[i] = surface.nearest(results[past[i]].far_point).distance; });
    const std::size_t worst = past[static_cast<std::size_t>(std::max_element(far.begin(), far.end()) - far.begin())];
    SplatPoints points;
    report.max_distance = measure_splat(ellipses[worst], worst, options, surface, INFINITY, points).max_distance;
    report.worst_splat = worst;
  }
  return report;
}

nlohmann::json to_json(const SurfaceCheckReport& r) {
  return {{"eps", r.eps},
          {"slack", r.slack},
          {"seed", r.seed},
          {"ok", r.ok()},
          {"surface",
           {{"area", r.surface_area},
            {"points", r.surface_points},
            {"points_wanted", r.surface_points_wanted},
            {"points_clamped", r.surface_points_clamped},
            {"uncovered_points", r.uncovered_points},
            {"uncovered_fraction", r.uncovered_fraction},
            {"holes", r.holes},
            {"largest_hole_points", r.largest_hole_points},
            {"largest_hole_area", r.largest_hole_area},
            {"largest_hole_diameter", r.largest_hole_diameter},
            {"largest_hole_diameter_eps", r.largest_hole_diameter / r.eps},
            {"hole_thinning", r.hole_thinning}}},
          {"splats",
           {{"count", r.splats},
            {"points", r.splat_points},
            {"max_distance", r.max_distance},
            {"max_distance_eps", r.max_distance_eps()},
            {"worst_splat", r.worst_splat},
            {"area_beyond_fraction", r.area_beyond_fraction},
            {"splats_beyond", r.splats_beyond},
            {"largest_major", r.largest_major},
            {"diagonal", r.diagonal},
            {"largest_major_diagonal", r.largest_major_diagonal()},
            {"flipped", r.flipped},
            {"degenerate", r.degenerate}}}};
}

std::string describe_failure(const SurfaceCheckReport& r, const Mesh* mesh) {
  std::string broken;
  const auto add = [&](const std::string& part) { broken += (broken.empty() ? "" : "; ") + part; };
  if (r.uncovered_points > 0)
    add(fmt::format("surface not covered within eps ({:.3g}% of the area uncovered, largest hole {:.3g} eps across)",
                    100 * r.uncovered_fraction, r.largest_hole_diameter / r.eps));
  if (r.splats_beyond > 0)
    add(fmt::format("{} splat{} the surface by more than eps (up to {:.3g} eps)", r.splats_beyond, r.splats_beyond == 1 ? " leaves" : "s leave",
                    r.max_distance_eps()));
  if (r.degenerate > 0) add(fmt::format("{} degenerate splat{}", r.degenerate, r.degenerate == 1 ? "" : "s"));
  // A mesh far from the origin reads with its vertices on a coarse float grid: the check measures
  // against that mesh, and its warning (printed only on success) is the cause a user needs.
  if (const std::string far = mesh ? float_step_warning(*mesh) : std::string(); !broken.empty() && !far.empty())
    add("the mesh's " + far);
  return broken;
}

SurfaceCheckReport check_before_writing(const Mesh& mesh, const std::vector<SplatRecord>& splats, bool surface_bound, double eps,
                                        const std::string& model, const std::string& remedy, const SurfaceCheckProgress& progress) {
  SurfaceCheckOptions options;
  options.eps = eps;
  SurfaceCheckReport report = check_surface(mesh, splats, options, progress);
  if (!report.ok() && surface_bound)
    throw Error(fmt::format("{}: the splats break the two-sided bound at eps {:.6g} ({}); nothing written{}", model, eps,
                            describe_failure(report, &mesh), remedy));
  return report;
}

}  // namespace splatcl::splats
