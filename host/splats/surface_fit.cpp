#include "splats/surface_fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>

#include "runtime/profiling.hpp"
#include "core/parallel.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/reference.hpp"

namespace splatcl::splats {
namespace {

// The checks run on the splats as floats will store them; this much of ε is kept in reserve for
// the rounding of the written values.
constexpr double kFloatReserve = 1e-4;
constexpr double kBetweenPointsReserve = 0.1;
// A splat's test points must lie within ε of a triangle whose plane is within 60° of the splat's
// (kFacingCos): beyond a crease sharper than that, only a sliver of at most ε / sin(angle) needs the
// other face. Fixed at the default crease angle, not the run's: at --crease-angle 180 (smooth frames
// across every edge) a splat tilted more than 60° off both faces of a knife edge shrinks away, and
// gap splats, in their triangles' planes, cover there instead.
// Squares a certification may visit before the splat counts as failing (and is made smaller).
constexpr std::size_t kCertifyBudget = 8192;
// Coverage cells are refined down to this fraction of ε; below it, a cell that no one splat holds
// whole is checked at its corners, edge midpoints and centre. At ε/16 a slit of ~ε/150 where
// three face-planar splats meet beside a crease slipped through (tests/splats/two_sided_test.cpp,
// the creased part); ε/64 doubles the gap search (bunny 224 → 457 ms).
constexpr double kFinestCell = 1.0 / 64.0;
// Check-and-fill rounds (the last only checks). The drawn splats' gaps on the creased part, whose
// few thesis splats leave nearly all of it to gap splats, take 6 rounds that fill; at 6 in all, 94
// cells were left uncovered (tests/splats/drawn_gaps_test.cpp).
constexpr std::size_t kMaxGapRounds = 10;
// Gap splats are made in parallel ahead of the walk that places them, from this far ahead, for
// gaps this many mean gap-splat sizes apart.
constexpr std::size_t kGapLookahead = 4096;
constexpr double kGapSpread = 4;
// The surface bound shrinks a grown splat from at most this aspect (bound_by_surface).
constexpr double kShrinkAspect = 4;

// In-plane coordinates of p relative to e, and its height above the plane.
struct Local {
  double x, y, h;
};
Local local(const Ellipse& e, DVec3 p) {
  const DVec3 w = p - e.center;
  return {dot(w, e.u), dot(w, e.v), dot(w, e.normal)};
}

bool inside(const Ellipse& e, double x, double y) {
  if (!(e.a > 0 && e.b > 0)) return false;
  if (!(x * x / (e.a * e.a) + y * y / (e.b * e.b) <= 1.0)) return false;
  return (!std::isfinite(e.clip_offset) || x * e.clip_x + y * e.clip_y <= e.clip_offset) &&
         (!std::isfinite(e.clip2_offset) || x * e.clip2_x + y * e.clip2_y <= e.clip2_offset);
}

// Whether e covers p on a surface triangle with normal `surface_normal`: facing the same way, the
// projection inside the (clipped) ellipse, within ε in height.
bool covers(const Ellipse& e, DVec3 p, DVec3 surface_normal, double eps) {
  if (!(dot(e.normal, surface_normal) > 0)) return false;
  const Local l = local(e, p);
  return std::fabs(l.h) <= eps && inside(e, l.x, l.y);
}

BoxTree::Box box_of(const Ellipse& e, double eps) {
  const auto half = [&](double u, double v, double n) { return std::sqrt(e.a * e.a * u * u + e.b * e.b * v * v) + eps * std::fabs(n) + eps; };
  const DVec3 h{half(e.u.x, e.v.x, e.normal.x), half(e.u.y, e.v.y, e.normal.y), half(e.u.z, e.v.z, e.normal.z)};
  BoxTree::Box box;
  box.add(e.center - h);
  box.add(e.center + h);
  return box;
}

SplatRecord record_of(const Ellipse& e, Rgba8 color) {
  SplatRecord r;
  r.center = to_float(e.center);
  r.normal = to_float(e.normal);
  r.major = to_float(e.a * e.u);
  r.minor = to_float(e.b * e.v);
  r.color = color;
  r.clip_x = static_cast<float>(e.clip_x), r.clip_y = static_cast<float>(e.clip_y);
  r.clip_offset = static_cast<float>(e.clip_offset);
  return r;
}

}  // namespace

Ellipse ellipse_of(const SplatRecord& s) {
  Ellipse e;
  e.center = DVec3(s.center);
  e.normal = normalized(DVec3(s.normal));
  e.a = length(DVec3(s.major)), e.b = length(DVec3(s.minor));
  e.u = e.a > 0 ? normalized(DVec3(s.major)) : any_perpendicular(e.normal);
  e.v = e.b > 0 ? normalized(DVec3(s.minor)) : normalized(cross(e.normal, e.u));
  e.clip_x = s.clip_x, e.clip_y = s.clip_y, e.clip_offset = s.clip_offset;
  return e;
}

Ellipse ellipse_of(const SplatShape& shape, const Vec4& clip, const Frame& frame) {
  Ellipse e;
  e.center = DVec3(xyz(shape.center));
  e.normal = DVec3(xyz(frame.n));
  e.u = DVec3(xyz(frame.u)), e.v = DVec3(xyz(frame.v));
  e.a = shape.major.w, e.b = shape.minor.w;
  e.clip_x = clip.x, e.clip_y = clip.y, e.clip_offset = clip.z;
  return e;
}

void ellipse_test_points(const Ellipse& e, double eps, std::vector<DVec3>& out) {
  out.clear();
  const bool clipped = std::isfinite(e.clip_offset);
  const auto add = [&](double x, double y) {
    if (clipped && x * e.clip_x + y * e.clip_y > e.clip_offset) return;
    out.push_back(e.center + x * e.u + y * e.v);
  };
  constexpr double kTau = 2 * std::numbers::pi;
  // The rim first: where a splat too large leaves the surface.
  const double perimeter = std::numbers::pi * (3 * (e.a + e.b) - std::sqrt((3 * e.a + e.b) * (e.a + 3 * e.b)));
  const int rim = static_cast<int>(std::clamp(std::ceil(perimeter / (2 * eps)), 24.0, 128.0));
  // In order round the rim: consecutive points mostly lie near the same triangles.
  for (int k = 0; k < rim; ++k) add(e.a * std::cos(kTau * k / rim), e.b * std::sin(kTau * k / rim));
  if (clipped) {
    // The chord x·c + y·s = offset inside the ellipse.
    const double px = e.clip_offset * e.clip_x, py = e.clip_offset * e.clip_y, dx = -e.clip_y, dy = e.clip_x;
    const double qa = dx * dx / (e.a * e.a) + dy * dy / (e.b * e.b), qb = 2 * (px * dx / (e.a * e.a) + py * dy / (e.b * e.b)),
                 qc = px * px / (e.a * e.a) + py * py / (e.b * e.b) - 1;
    const double disc = qb * qb - 4 * qa * qc;
    if (qa > 0 && disc > 0) {
      const double t0 = (-qb - std::sqrt(disc)) / (2 * qa), t1 = (-qb + std::sqrt(disc)) / (2 * qa);
      for (int k = 0; k <= 8; ++k) {
        const double t = t0 + (t1 - t0) * k / 8;
        out.push_back(e.center + (px + t * dx) * e.u + (py + t * dy) * e.v);
      }
    }
  }
  for (const auto& [rho, count] : {std::pair{0.5, 8}})
    for (int k = 0; k < count; ++k) add(rho * e.a * std::cos(kTau * (k + 0.5) / count), rho * e.b * std::sin(kTau * (k + 0.5) / count));
  add(0, 0);
}

float growth_eps(float eps) { return static_cast<float>(eps * (1 - kFloatReserve) * (1 - kBetweenPointsReserve)); }

bool within_surface(const Surface& surface, const Ellipse& e, double eps, std::vector<DVec3>& scratch, Surface::Recent* recent) {
  ellipse_test_points(e, eps, scratch);
  // The points are a sample of the ellipse: between them the distance can rise by a little more
  // (it is 1-Lipschitz), so they must keep this much below ε.
  const double limit = eps * (1 - kBetweenPointsReserve);
  Surface::Recent own;
  if (!recent) recent = &own;
  // Near a surface that faces its way: a splat standing across a face within ε of it (a strip in a
  // hole's wall laid along the rim over the plate's top) passed on distance alone, and showed as a
  // line of the wall's normal across the face.
  const Surface::Facing facing{e.normal, kFacingCos};
  for (const DVec3& p : scratch)
    if (!surface.within(p, limit, recent, &facing)) return false;
  return true;
}

// Whether every corner of the parallelogram centre ± hu ± hv lies within ε of triangle t: the
// distance to a triangle is convex, so then all of the parallelogram does.
bool parallelogram_within(const SurfaceTriangle& t, DVec3 centre, DVec3 hu, DVec3 hv, double eps) {
  const DVec3 corners[4] = {centre - hu - hv, centre - hu + hv, centre + hu - hv, centre + hu + hv};
  // A corner farther than ε from the ball of the triangle's corners or from its plane is farther
  // from the triangle: the cheap tests first, for all four, since most candidates fail.
  const double reach = t.reach + eps;
  for (const DVec3& corner : corners) {
    const DVec3 w = corner - t.centroid;
    if (!(dot(w, w) <= reach * reach) || !(std::fabs(dot(corner - t.a, t.normal)) <= eps)) return false;
  }
  for (const DVec3& corner : corners) {
    const DVec3 d = closest_point(t, corner) - corner;
    if (!(dot(d, d) <= eps * eps)) return false;
  }
  return true;
}

namespace {

// The largest value in [lo, hi] that passes a test that holds up to some value and fails beyond it,
// for lo passing: bisection, at most `steps` halvings and only while hi > lo · ratio.
template <class Passes>
double largest_passing(double lo, double hi, int steps, double ratio, const Passes& passes) {
  for (int step = 0; step < steps && hi > lo * ratio; ++step) {
    const double mid = 0.5 * (lo + hi);
    (passes(mid) ? lo : hi) = mid;
  }
  return lo;
}

// The largest value from lo (passing) on, up to `largest`, that passes: doubling from `start`, then
// bisection.
template <class Passes>
double grow_while_passing(double lo, double start, double largest, const Passes& passes) {
  double hi = start;
  while (hi < largest && passes(hi)) lo = hi, hi *= 2;
  if (hi >= largest && lo > 0 && passes(largest)) return largest;
  // Not beyond `largest`: the surface test is sampled, so not strictly monotonic.
  return largest_passing(lo, std::min(hi, largest), 5, 1.15, passes);
}

}  // namespace

bool certified_within_surface(const Surface& surface, const Ellipse& e, double eps) {
  if (!(e.a > 0 && e.b > 0)) return true;
  // Rectangles of the ellipse's parameter domain [-1, 1]², split in four while roughly square in
  // space (fewer rectangles tested on the way down than halving), else across their longer side;
  // one maps to a parallelogram of circumradius r around its centre q. The distance to the surface
  // is 1-Lipschitz, so D(q) + r <= ε certifies the whole rectangle; so does one triangle within ε
  // of all four corners (the distance to one triangle is convex).
  struct Rect {
    double s, t, hs, ht;
  };
  const double finest = eps / 16;
  const bool clipped = std::isfinite(e.clip_offset);
  const double cx = e.a * e.clip_x, cy = e.b * e.clip_y;  // the clip's linear form in (s, t)
  const auto& triangles = surface.triangles();
  std::vector<Rect> stack{{0, 0, 1, 1}};
  Surface::Recent recent;  // the last answers, mostly the triangles under the last rectangles
  std::size_t visited = 0;
  while (!stack.empty()) {
    const Rect q = stack.back();
    stack.pop_back();
    if (++visited > kCertifyBudget) return false;
    // Rectangles wholly outside the unit disk or beyond the clip line hold no point of the splat.
    const double ns = std::max(0.0, std::fabs(q.s) - q.hs), nt = std::max(0.0, std::fabs(q.t) - q.ht);
    if (ns * ns + nt * nt > 1) continue;
    if (clipped && cx * q.s + cy * q.t - (q.hs * std::fabs(cx) + q.ht * std::fabs(cy)) > e.clip_offset) continue;
    const double radius = std::sqrt(e.a * e.a * q.hs * q.hs + e.b * e.b * q.ht * q.ht);
    const bool centre_inside = q.s * q.s + q.t * q.t <= 1 && (!clipped || cx * q.s + cy * q.t <= e.clip_offset);
    const DVec3 centre = e.center + (e.a * q.s) * e.u + (e.b * q.t) * e.v;
    const DVec3 hu = (e.a * q.hs) * e.u, hv = (e.b * q.ht) * e.v;
    // The recent answers first (neighbouring rectangles mostly lie over the same triangles), then
    // the nearest triangle.
    // The Lipschitz test can pass only for a rectangle smaller than ε around an inside centre.
    const bool lipschitz = centre_inside && radius <= eps;
    const auto certifies = [&](std::uint32_t t, double distance) {
      return (lipschitz && distance + radius <= eps) || parallelogram_within(triangles[t], centre, hu, hv, eps);
    };
    bool done = false;
    for (const std::uint32_t t : recent.triangles)
      if (t != UINT32_MAX && !done) done = certifies(t, lipschitz ? length(closest_point(triangles[t], centre) - centre) : INFINITY);
    if (done) continue;
    const Surface::Nearest nearest = surface.nearest(centre, eps, &recent);
    if (nearest.triangle != UINT32_MAX) {
      if (certifies(nearest.triangle, nearest.distance)) continue;
    } else if (centre_inside) {
      return false;  // a point of the splat farther than ε
    }
    if (radius <= finest) {
      if (centre_inside) return false;
      // The rectangle's part inside the disk lies within 2r of the centre's nearest disk point.
      const double norm = std::sqrt(q.s * q.s + q.t * q.t);
      const DVec3 p = e.center + (e.a * q.s / norm) * e.u + (e.b * q.t / norm) * e.v;
      if (!surface.within(p, eps - 2 * radius, &recent)) return false;
      continue;
    }
    if (e.a * q.hs <= 2 * e.b * q.ht && e.b * q.ht <= 2 * e.a * q.hs) {
      for (const double ds : {-0.5, 0.5})
        for (const double dt : {-0.5, 0.5}) stack.push_back({q.s + ds * q.hs, q.t + dt * q.ht, q.hs / 2, q.ht / 2});
    } else if (e.a * q.hs >= e.b * q.ht) {
      stack.push_back({q.s - q.hs / 2, q.t, q.hs / 2, q.ht});
      stack.push_back({q.s + q.hs / 2, q.t, q.hs / 2, q.ht});
    } else {
      stack.push_back({q.s, q.t - q.ht / 2, q.hs, q.ht / 2});
      stack.push_back({q.s, q.t + q.ht / 2, q.hs, q.ht / 2});
    }
  }
  return true;
}

bool shrink_until_certified(const Surface& surface, Ellipse& e, double eps) {
  for (int step = 0; step < 24; ++step) {
    if (certified_within_surface(surface, e, eps)) return true;
    e.a *= 0.85, e.b *= 0.85;
  }
  e.a = e.b = 0;
  return false;
}

void bound_by_surface(const Surface& surface, const Samples& samples, const Neighborhoods& neighbors, FitResult& fit,
                      float eps_float, SurfaceFitStats& stats) {
  Stopwatch clock;
  const double eps = eps_float * (1 - kFloatReserve);
  const std::size_t n = fit.splats.size();
  std::vector<std::uint8_t> shrunk(n, 0);
  std::vector<std::vector<DVec3>> scratch(worker_count(n, 32));
  parallel_for(n, 32, [&](std::size_t i, std::size_t worker) {
    SplatShape& shape = fit.splats[i];
    Ellipse e = ellipse_of(shape, fit.clips[i], fit.frames[i]);
    if (!(e.a > 0 && e.b > 0)) {
      shrunk[i] = 1;  // zero size: its sets are emptied below
      return;
    }
    const double a0 = e.a;
    // The ellipse phase's major can reach far beyond the model (a minor of 16 ε with a major of
    // 200,000 ε on an octahedron). Scaled down whole, such a splat became a needle (a minor of
    // ε/130, aspect 13,000:1); it is shrunk from kShrinkAspect times its minor instead, and its
    // major then extended as far as it passes.
    const double b0 = e.b, a1 = std::min(a0, kShrinkAspect * b0);
    Surface::Recent recent;  // the tests at several sizes query the same part of the surface
    const auto passes = [&](double a, double b) {
      e.a = a, e.b = b;
      return within_surface(surface, e, eps, scratch[worker], &recent);
    };
    const auto test = [&](double s, double t) { return passes(s * a1 + t * (a1 - s * a1), s * b0); };  // scale s, major extended by t
    if (a1 < a0 && passes(a0, b0)) return;
    // A first guess from the samples: the scale at which the nearest same-facing neighbour of the
    // covered samples that lies more than ε off the splat's plane projects onto its rim.
    double guess = 1;
    for (const std::uint32_t* m = fit.covered.begin(i); m != fit.covered.end(i); ++m) {
      for (const std::uint32_t* q = neighbors.row(*m); q != neighbors.row(*m) + neighbors.k; ++q) {
        const Local l = local(e, DVec3(xyz(samples.positions[*q])));
        if (std::fabs(l.h) <= eps || dot(DVec3(xyz(samples.normals[*q])), e.normal) <= 0) continue;
        guess = std::min(guess, std::sqrt(l.x * l.x / (a1 * a1) + l.y * l.y / (b0 * b0)));
      }
    }
    // The guess first (the whole splat when the samples suggest nothing), then halving.
    guess = std::max(guess, 1.0 / 16);
    double lo = 0, hi = 1;
    if (test(guess, 0)) {
      if (guess == 1 && a1 == a0) return;
      lo = guess;
    } else {
      hi = guess;
    }
    for (int step = 0; step < (lo > 0 ? 2 : 4) && lo < 1; ++step) {
      const double s = 0.5 * (lo + hi);
      (test(s, 0) ? lo : hi) = s;
    }
    // Below every tested scale: halve on (a splat at a mesh boundary or a spike may pass only
    // tiny); one that passes at no scale is left with zero size and gives way to gap filling.
    while (lo == 0 && hi > 1.0 / 4096) {
      hi *= 0.5;
      if (test(hi, 0)) lo = hi;
    }
    double fa_double = lo * a1;  // as much of the major axis back as still passes
    if (lo > 0 && a1 < a0) {
      fa_double = grow_while_passing(fa_double, 2 * fa_double, a0, [&](double a) { return passes(a, lo * b0); });
    } else if (a1 > b0 * 1.25 && lo < 1 && test(lo, 0.5)) {
      fa_double = lo * a1 + 0.5 * (a1 - lo * a1);
    }
    const float fb = static_cast<float>(lo * b0), fa = static_cast<float>(fa_double);
    const Vec3 u = xyz(fit.frames[i].u), v = xyz(fit.frames[i].v);
    shape.major = {u.x * fa, u.y * fa, u.z * fa, fa};
    shape.minor = {v.x * fb, v.y * fb, v.z * fb, fb};
    shrunk[i] = 1;
  });
  // A shrunk splat covers the samples still inside it, and its safe set is those without their
  // new convex hull (the growth's rule, the splat thesis §2.2.3).
  std::vector<std::vector<std::uint32_t>> sets(n);
  parallel_for(n, 64, [&](std::size_t i, std::size_t) {
    std::vector<std::uint32_t>& set = sets[i];
    const std::uint32_t* safe = fit.safe.begin(i);
    if (!shrunk[i]) {
      // The hull bits back from the two rows (both in acceptance order).
      for (const std::uint32_t* m = fit.covered.begin(i); m != fit.covered.end(i); ++m) {
        const bool is_safe = safe != fit.safe.end(i) && *safe == *m;
        set.push_back(is_safe ? *m : (*m | kOnHullBit));
        if (is_safe) ++safe;
      }
      return;
    }
    const Ellipse e = ellipse_of(fit.splats[i], fit.clips[i], fit.frames[i]);
    if (!(e.a > 0 && e.b > 0)) return;  // zero size: it covers no sample, and gap filling covers its surface
    for (const std::uint32_t* m = fit.covered.begin(i); m != fit.covered.end(i); ++m) {
      const Local l = local(e, DVec3(xyz(samples.positions[*m])));
      if (*m == i || inside(e, l.x, l.y)) set.push_back(*m);
    }
    reference::mark_hull_points(samples, xyz(fit.splats[i].center), xyz(fit.frames[i].u), xyz(fit.frames[i].v), set);
  });
  set_rows(sets, fit);
  stats.shrunk += static_cast<std::size_t>(std::count(shrunk.begin(), shrunk.end(), 1));
  stats.bound_ms += clock.elapsed_ms();
}

namespace {

struct Gap {
  DVec3 point;
  std::uint32_t triangle;
};

// The gaps of every triangle's cells, refined down to kFinestCell · ε, in triangle order.
std::vector<Gap> find_gaps(const Surface& surface, const std::vector<Ellipse>& splats, const BoxTree& tree, double eps,
                           std::size_t& cells_checked, const std::vector<std::uint32_t>* only) {
  const auto& triangles = surface.triangles();
  const std::size_t count = only ? only->size() : triangles.size();
  std::vector<std::vector<Gap>> per_triangle(count);
  std::vector<std::size_t> cells(worker_count(count, 64), 0);
  const double finest = kFinestCell * eps;
  parallel_for(count, 64, [&](std::size_t r, std::size_t worker) {
    const std::uint32_t t = only ? (*only)[r] : static_cast<std::uint32_t>(r);
    const SurfaceTriangle& tri = triangles[t];
    struct Cell {
      DVec3 p0, p1, p2;
    };
    std::vector<Cell> stack{{tri.a, tri.b, tri.c}};
    while (!stack.empty()) {
      const Cell c = stack.back();
      stack.pop_back();
      ++cells[worker];
      // What one splat covers (its elliptic cylinder within the ±ε slab, on the kept side of its
      // clip line, facing the triangle's way) is convex, and so is the cell: a splat that covers
      // the three corners covers the whole cell.
      bool covered = false;
      double query = 0;
      tree.visit(c.p0, query, [&](std::uint32_t j, double&) {
        const Ellipse& e = splats[j];
        return covered = covers(e, c.p0, tri.normal, eps) && covers(e, c.p1, tri.normal, eps) && covers(e, c.p2, tri.normal, eps);
      });
      if (covered) continue;
      const auto covered_point = [&](DVec3 p) {
        bool hit = false;
        double zero = 0;
        tree.visit(p, zero, [&](std::uint32_t j, double&) { return hit = covers(splats[j], p, tri.normal, eps); });
        return hit;
      };
      const DVec3 g = (1.0 / 3.0) * (c.p0 + c.p1 + c.p2);
      // An uncovered centre is a gap at once: the splat made there takes most of the cell, and the
      // next round checks what is left.
      if (!covered_point(g)) {
        per_triangle[r].push_back({g, t});
        continue;
      }
      const DVec3 m01 = 0.5 * (c.p0 + c.p1), m12 = 0.5 * (c.p1 + c.p2), m20 = 0.5 * (c.p2 + c.p0);
      const double radius = std::max({length(c.p0 - g), length(c.p1 - g), length(c.p2 - g)});
      if (radius <= finest) {
        // Covered only by several splats together at this scale: its corners and edge midpoints
        // must be covered too.
        for (const DVec3 p : {c.p0, c.p1, c.p2, m01, m12, m20}) {
          if (covered_point(p)) continue;
          per_triangle[r].push_back({p, t});
          break;
        }
        continue;
      }
      // Midpoint subdivision keeps a cell's shape: a needle's cells stay needles, refined until
      // their length reaches the finest size, so a splat's rim across a needle of aspect A is
      // tracked by cells A times narrower than the finest (a fan of 1,500 needles: 37M cells, 8.6M
      // gaps). A needle (one edge under half the other two) is cut across instead, into its apex
      // half and the two halves of the trapezoid left (its aspect halves each level), and a cap
      // (an obtuse sliver: the longest edge over 4 times its height) at its longest edge's
      // midpoint, into two needles; the cells then reach the finest size with bounded aspect.
      const DVec3 p[3] = {c.p0, c.p1, c.p2};
      const double l2[3] = {dot(p[1] - p[2], p[1] - p[2]), dot(p[2] - p[0], p[2] - p[0]), dot(p[0] - p[1], p[0] - p[1])};  // opposite p[k]
      const int lo = l2[0] <= l2[1] && l2[0] <= l2[2] ? 0 : l2[1] <= l2[2] ? 1 : 2;  // opposite the shortest edge
      const int hi = l2[0] >= l2[1] && l2[0] >= l2[2] ? 0 : l2[1] >= l2[2] ? 1 : 2;  // opposite the longest edge
      const DVec3 o = p[lo], a = p[(lo + 1) % 3], b = p[(lo + 2) % 3];
      const DVec3 n = cross(p[1] - p[0], p[2] - p[0]);
      if (4 * l2[lo] < std::min(l2[(lo + 1) % 3], l2[(lo + 2) % 3])) {
        const DVec3 oa = 0.5 * (o + a), ob = 0.5 * (o + b);
        stack.push_back({o, oa, ob});
        stack.push_back({oa, a, b});
        stack.push_back({oa, b, ob});
      } else if (l2[hi] * l2[hi] > 16 * dot(n, n)) {  // height 2·area/longest below longest/4
        const DVec3 v = p[hi], x = p[(hi + 1) % 3], y = p[(hi + 2) % 3], mid = 0.5 * (x + y);
        stack.push_back({v, x, mid});
        stack.push_back({v, mid, y});
      } else {
        stack.push_back({m01, m12, m20});
        stack.push_back({m20, m12, c.p2});
        stack.push_back({m01, c.p1, m12});
        stack.push_back({c.p0, m01, m20});
      }
    }
  });
  for (const std::size_t c : cells) cells_checked += c;
  std::vector<Gap> gaps;
  for (auto& list : per_triangle) gaps.insert(gaps.end(), list.begin(), list.end());
  return gaps;
}

// An ellipse in the triangle's plane centred on the gap, as large as the surface bound allows (up
// to `largest`): the largest passing circle, then, of the orientations of the major axis tried
// (four from the longest edge, and along the other edges), the one that passes at the greatest
// length (along a crease or a boundary, the surface allows a long thin splat where a circle stays
// small).
// `same_colour`, when set, must also pass: the colour variant's tolerance over the splat.
using ColourTest = std::function<bool(const Ellipse&, Surface::Recent&)>;
Ellipse gap_splat(const Surface& surface, const Gap& gap, double eps, double largest, std::vector<DVec3>& scratch,
                  const ColourTest& same_colour) {
  const SurfaceTriangle& t = surface.triangles()[gap.triangle];
  Ellipse e;
  e.center = gap.point;
  e.normal = t.normal;
  const DVec3 edges[3] = {t.b - t.a, t.c - t.b, t.a - t.c};
  const DVec3 longest = *std::max_element(edges, edges + 3, [](DVec3 p, DVec3 q) { return dot(p, p) < dot(q, q); });
  DVec3 x = normalized(longest - dot(longest, e.normal) * e.normal);
  if (!(length(x) > 0)) x = any_perpendicular(e.normal);
  const DVec3 y = cross(e.normal, x);
  e.u = x, e.v = y;
  Surface::Recent recent;  // the tests at several sizes query the same part of the surface
  const auto test = [&](double a, double b) {
    e.a = a, e.b = b;
    return within_surface(surface, e, eps, scratch, &recent) && (!same_colour || same_colour(e, recent));
  };
  double radius = grow_while_passing(0.0, 2 * eps, largest, [&](double r) { return test(r, r); });
  for (double r = eps / 32; !(radius > 0) && r > eps / 4096; r *= 0.5)
    if (test(r, r)) radius = r;
  if (!(radius > 0)) radius = eps / 4096;  // the centre itself lies on the surface
  // Major axes to try: four from the longest edge, and along the triangle's other two edges (the
  // sides of a quad split on its diagonal: on a 1 x 2 face no multiple of 45 degrees from the
  // diagonal runs along the face's border, and its gaps took 13x the splats of a square's).
  std::vector<DVec3> directions;
  for (int k = 0; k < 4; ++k) {
    const double angle = std::numbers::pi * k / 4;
    directions.push_back(std::cos(angle) * x + std::sin(angle) * y);
  }
  for (const DVec3& edge : edges) {
    const DVec3 along = normalized(edge - dot(edge, e.normal) * e.normal);
    if (!(length(along) > 0)) continue;
    // Not one already tried (within about 3 degrees, either way along).
    if (std::none_of(directions.begin(), directions.end(), [&](DVec3 d) { return std::fabs(dot(d, along)) > 0.9986; }))
      directions.push_back(along);
  }
  double best_a = radius;
  DVec3 best_u = x;
  for (const DVec3& direction : directions) {
    e.u = direction;
    e.v = cross(e.normal, e.u);
    const double a = grow_while_passing(radius, 2 * radius, largest, [&](double a_) { return test(a_, radius); });
    if (a > best_a * 1.05) best_a = a, best_u = e.u;
  }
  e.u = best_u, e.v = cross(e.normal, best_u);
  e.a = best_a, e.b = radius;
  return e;
}

Rgba8 color_at(const Mesh& mesh, const ColorSource& colors, const SurfaceTriangle& t, DVec3 p) {
  if (!mesh.has_texcoords()) return colors.at(to_float(p), nullptr);
  const Barycentric w = barycentric(t, p);
  float uv[2];
  for (int k = 0; k < 2; ++k)
    uv[k] = static_cast<float>(w.a * mesh.corner_texcoords[t.corners[0]][k] + w.b * mesh.corner_texcoords[t.corners[1]][k] +
                               w.c * mesh.corner_texcoords[t.corners[2]][k]);
  return colors.at(to_float(p), uv);
}

// Whether the surface under e, its axes shortened by `margin` (to 0 at least), shows `colour` within `tolerance`
// on every channel (the splat thesis's colour test, §2.3.2), at the rim and three inner rings: the
// points' nearest surface points, their colours as the samples got theirs.
bool keeps_colour(const Surface& surface, const Mesh& mesh, const ColorSource& colors, const Ellipse& e, double eps, Rgba8 colour,
                  int tolerance, double margin, Surface::Recent& recent) {
  constexpr double kTau = 2 * std::numbers::pi;
  // A splat thinner than twice the margin is tested along its major axis.
  const double a = std::max(e.a - margin, 0.0), b = std::max(e.b - margin, 0.0);
  if (!(std::max(a, b) > 0)) return true;
  const auto holds = [&](double x, double y) {
    const DVec3 p = e.center + x * e.u + y * e.v;
    const Surface::Nearest near = surface.nearest(p, 2 * eps, &recent);
    if (near.triangle == UINT32_MAX) return false;
    const SurfaceTriangle& t = surface.triangles()[near.triangle];
    const Rgba8 c = color_at(mesh, colors, t, closest_point(t, p));
    return reference::color_similar(c, colour, tolerance);
  };
  for (const auto& [rho, count] : {std::pair{1.0, 64}, std::pair{0.75, 48}, std::pair{0.5, 32}, std::pair{0.25, 16}})
    for (int k = 0; k < count; ++k)
      if (!holds(rho * a * std::cos(kTau * k / count), rho * b * std::sin(kTau * k / count))) return false;
  return true;
}

}  // namespace

namespace {

// The gap rounds of fill_gaps and cover_drawn_gaps: checks the surface against `splats` within
// `eps` (added splats are appended to it) and adds a splat at each gap, made by gap_splat and
// certified within `eps` as drawn, with both axes times `scale`; `color(ellipse, triangle)` colours
// it. Returns the added splats.
template <class Color>
std::vector<SplatRecord> add_gap_splats(const Surface& surface, std::vector<Ellipse>& splats, double eps, double scale,
                                        double largest, const Color& color, SurfaceFitStats& stats,
                                        const std::function<ColourTest(const Gap&)>& colour_test = {},
                                        const std::function<void(const std::string&)>& progress = {}) {
  std::vector<SplatRecord> added;
  std::vector<std::uint32_t> recheck;  // triangles that had gaps: the later rounds check only them
  for (std::size_t round = 0; round < kMaxGapRounds; ++round) {
    std::vector<BoxTree::Box> boxes(splats.size());
    for (std::size_t j = 0; j < splats.size(); ++j) boxes[j] = box_of(splats[j], eps);
    const BoxTree tree(boxes);
    Stopwatch search_clock;
    const std::vector<Gap> gaps = find_gaps(surface, splats, tree, eps, stats.cells_checked, round ? &recheck : nullptr);
    stats.gap_search_ms += search_clock.elapsed_ms();
    stats.uncovered_cells = gaps.size();
    if (gaps.empty()) break;
    ++stats.gap_rounds;
    recheck.clear();
    for (const Gap& g : gaps)
      if (recheck.empty() || recheck.back() != g.triangle) recheck.push_back(g.triangle);
    if (round + 1 == kMaxGapRounds) break;
    // Gaps in order; a gap that a splat added before it in this round covers needs none.
    std::vector<BoxTree::Box> points(gaps.size());
    for (std::size_t r = 0; r < gaps.size(); ++r) points[r].add(gaps[r].point);
    const BoxTree gap_tree(points);
    std::vector<std::uint8_t> done(gaps.size(), 0);
    const auto mark_covered = [&](const Ellipse& e) {
      double reach = std::max(e.a, e.b) + eps;
      gap_tree.visit(e.center, reach, [&](std::uint32_t q, double&) {
        if (!done[q] && covers(e, gaps[q].point, surface.triangles()[gaps[q].triangle].normal, eps)) done[q] = 1;
        return false;
      });
    };
    // A gap's splat depends on the gap alone, so splats are made ahead of the walk in order, in
    // parallel, for the gap at hand and the next open gaps spread apart from it and each other
    // (by kGapSpread mean sizes of the gap splats so far): the same splats as one at a time, and
    // little thrown away (a splat made for a gap that is covered by the time the walk gets there).
    std::vector<std::uint32_t> slot(gaps.size(), UINT32_MAX);
    std::vector<Ellipse> made;
    std::vector<std::uint8_t> fits;
    std::vector<std::vector<DVec3>> scratch(worker_count(SIZE_MAX, 1));  // one gap per thread
    std::vector<std::size_t> batch;
    double size_sum = 0;
    std::size_t size_count = 0;
    for (std::size_t r = 0; r < gaps.size(); ++r) {
      // Rounds of many gaps take minutes on a large scan at a small ε (the bunny at 3e-4 of its
      // diagonal: 31 s without a progress line).
      if (progress && r % 1024 == 0)
        progress(fmt::format("gap fill round {}: {} of {} uncovered cells filled or tried, {} splats added", round + 1, r, gaps.size(),
                             added.size()));
      if (done[r]) continue;
      done[r] = 1;  // without a fitting splat, the next round reports it if nothing else covers it
      if (slot[r] == UINT32_MAX) {
        const double spread = size_count > 0 ? kGapSpread * size_sum / static_cast<double>(size_count) : 8 * eps;
        batch.assign(1, r);
        for (std::size_t q = r + 1; q < gaps.size() && q < r + kGapLookahead && batch.size() < scratch.size(); ++q) {
          if (done[q] || slot[q] != UINT32_MAX) continue;
          if (std::all_of(batch.begin(), batch.end(), [&](std::size_t b) { return length(gaps[q].point - gaps[b].point) > spread; }))
            batch.push_back(q);
        }
        const std::size_t base = made.size();
        made.resize(base + batch.size());
        fits.resize(base + batch.size());
        for (std::size_t i = 0; i < batch.size(); ++i) slot[batch[i]] = static_cast<std::uint32_t>(base + i);
        parallel_for(batch.size(), 1, [&](std::size_t i, std::size_t worker) {
          // A plane's distance from a smooth surface grows with the square of the distance from
          // where it touches: made within eps / scale², it mostly passes as drawn at once.
          Ellipse e = gap_splat(surface, gaps[batch[i]], eps / (scale * scale), largest, scratch[worker],
                                colour_test ? colour_test(gaps[batch[i]]) : ColourTest{});
          e.a *= scale, e.b *= scale;
          fits[base + i] = shrink_until_certified(surface, e, eps);
          e.a /= scale, e.b /= scale;
          made[base + i] = e;
        });
      }
      if (!fits[slot[r]]) continue;
      const Ellipse& e = made[slot[r]];
      size_sum += std::max(e.a, e.b), ++size_count;
      mark_covered(e);
      splats.push_back(e);
      added.push_back(record_of(e, color(e, gaps[r].triangle)));
    }
  }
  stats.gap_splats += added.size();
  return added;
}

}  // namespace

std::vector<SplatRecord> fill_gaps(const Surface& surface, const Mesh& mesh, const ColorSource& colors, const GapColour& colour,
                                   std::vector<SplatRecord>& selected, float eps_float, SurfaceFitStats& stats,
                                   const std::function<void(const std::string&)>& progress) {
  Stopwatch clock;
  if (progress) progress(fmt::format("gap fill: certifying {} splats", selected.size()));
  const double eps = eps_float * (1 - kFloatReserve);
  // With the colour variant on a coloured mesh every splat keeps to its colour up to the margin: a
  // grown one to its start sample's, an added one to its gap's. The growth tests only the samples
  // its walk meets (the thesis's rings), so a grown splat could reach over a colour edge between
  // them; and a thin coloured plate, covered by gap splats alone, showed one colour over several
  // checker cells.
  const bool colour_varies = colour.tolerance < 255 && (colors.texture || colors.field != ColorField::Grey);
  const auto same_colour = [&](Rgba8 wanted) -> ColourTest {
    return [&, wanted](const Ellipse& e, Surface::Recent& recent) {
      return keeps_colour(surface, mesh, colors, e, eps, wanted, colour.tolerance, colour.margin, recent);
    };
  };
  // Every selected splat certified first: the bound's test points are a sample of the ellipse, and
  // between them the distance can rise (at a boundary, a crease or a bump). Then kept to its
  // colour: its major axis shortened (to the minor at most), else both axes shrunk; a smaller
  // ellipse with the same centre lies inside the certified one.
  std::vector<Ellipse> certified(selected.size());
  std::vector<std::uint8_t> changed(selected.size(), 0);
  Stopwatch certify_clock;
  parallel_for(selected.size(), 16, [&](std::size_t j, std::size_t) {
    Ellipse& e = certified[j];
    e = ellipse_of(selected[j]);
    const double a = e.a, b = e.b;
    shrink_until_certified(surface, e, eps);
    if (colour_varies && e.a > 0) {
      const ColourTest keeps = same_colour(selected[j].color);
      Surface::Recent recent;
      // Sets the largest size in [lo, hi] whose ellipse keeps the colour (lo is taken to).
      const auto shrink_to_colour = [&](double lo, double hi, const auto& set) {
        set(largest_passing(lo, hi, 10, 1.0, [&](double x) {
          set(x);
          return keeps(e, recent);
        }));
      };
      if (!keeps(e, recent)) {
        const double major = e.a, minor = e.b;
        e.a = minor;
        if (keeps(e, recent))
          shrink_to_colour(minor, major, [&](double x) { e.a = x; });
        else
          shrink_to_colour(std::min(minor, colour.margin), minor, [&](double x) { e.a = e.b = x; });
      }
    }
    changed[j] = e.a != a || e.b != b;
  });
  stats.certify_ms += certify_clock.elapsed_ms();
  std::vector<Ellipse> splats;
  splats.reserve(selected.size());
  std::vector<SplatRecord> kept;
  for (std::size_t j = 0; j < selected.size(); ++j) {
    stats.recertified += changed[j];
    if (!(certified[j].a > 0)) continue;
    splats.push_back(certified[j]);
    kept.push_back(changed[j] ? record_of(certified[j], selected[j].color) : selected[j]);
  }
  selected = std::move(kept);
  const auto gap_colour = [&](const Ellipse& e, std::uint32_t triangle) {
    return color_at(mesh, colors, surface.triangles()[triangle], e.center);
  };
  std::function<ColourTest(const Gap&)> colour_test;
  if (colour_varies)
    colour_test = [&](const Gap& gap) { return same_colour(color_at(mesh, colors, surface.triangles()[gap.triangle], gap.point)); };
  std::vector<SplatRecord> added =
      add_gap_splats(surface, splats, eps, 1.0, 0.25 * mesh.bounds().diagonal(), gap_colour, stats, colour_test, progress);
  stats.cover_ms += clock.elapsed_ms();
  return added;
}

std::vector<SplatRecord> cover_drawn_gaps(const Surface& surface, const std::vector<SplatRecord>& splats,
                                          const std::vector<ClipLine>& second_lines, double tolerance, double scale,
                                          SurfaceFitStats& stats) {
  Stopwatch clock;
  std::vector<Ellipse> fitted(splats.size());
  std::vector<BoxTree::Box> centres(splats.size());
  for (std::size_t j = 0; j < splats.size(); ++j) {
    Ellipse& e = fitted[j];
    e = ellipse_of(splats[j]);
    if (j < second_lines.size())
      e.clip2_x = second_lines[j].x, e.clip2_y = second_lines[j].y, e.clip2_offset = second_lines[j].offset;
    centres[j].add(e.center);
  }
  BoxTree::Box bounds;  // the mesh's: gap splats are at most a quarter of its diagonal, as in fill_gaps
  for (const SurfaceTriangle& t : surface.triangles()) bounds.add(t.a), bounds.add(t.b), bounds.add(t.c);
  const BoxTree centre_tree(centres);
  // The nearest same-facing splat within a few gap-splat sizes, else the nearest of any facing (a
  // search that only lowers its radius on a same-facing one could walk every splat of a mesh whose
  // splats all face away from the gap).
  const auto nearest_colour = [&](const Ellipse& e, std::uint32_t) {
    Rgba8 colour{128, 128, 128, 255};
    double radius = 8 * std::max(e.a, e.b) + 8 * tolerance;
    bool found = false;
    centre_tree.visit(e.center, radius, [&](std::uint32_t j, double& r) {
      const double d = length(fitted[j].center - e.center);
      if (d < r && dot(fitted[j].normal, e.normal) > 0) r = d, colour = splats[j].color, found = true;
      return false;
    });
    if (found) return colour;
    radius = INFINITY;
    centre_tree.visit(e.center, radius, [&](std::uint32_t j, double& r) {
      const double d = length(fitted[j].center - e.center);
      if (d < r) r = d, colour = splats[j].color;
      return false;
    });
    return colour;
  };
  std::vector<SplatRecord> added =
      add_gap_splats(surface, fitted, tolerance, scale, 0.25 * length(bounds.hi - bounds.lo), nearest_colour, stats);
  stats.cover_ms += clock.elapsed_ms();
  return added;
}

namespace {

// A line through points in a plane, fitted by total least squares: unit normal, its offset
// (n · p = offset on the line) and the largest distance of a point from it.
struct FittedLine {
  double nx = 0, ny = 0, offset = 0, residual = INFINITY;
};
FittedLine fit_line(const double* x, const double* y, std::size_t count) {
  FittedLine line;
  if (count < 2) return line;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < count; ++i) mx += x[i], my += y[i];
  mx /= static_cast<double>(count), my /= static_cast<double>(count);
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double dx = x[i] - mx, dy = y[i] - my;
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
  }
  // The normal is the eigenvector of the smaller eigenvalue of the 2 × 2 scatter matrix.
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);  // direction of the larger one
  line.nx = -std::sin(angle), line.ny = std::cos(angle);
  line.offset = line.nx * mx + line.ny * my;
  line.residual = 0;
  for (std::size_t i = 0; i < count; ++i) line.residual = std::max(line.residual, std::fabs(line.nx * x[i] + line.ny * y[i] - line.offset));
  return line;
}

}  // namespace

SurfaceClipStats clip_to_surface(const Surface& surface, std::vector<SplatRecord>& splats, double tolerance, double scale,
                                 std::vector<ClipLine>& second_lines) {
  // 16 directions find the splats that leave the surface; those are measured again along 64, whose
  // ends on the surface trace where it ends.
  constexpr int kCoarse = 16, kDirections = 64, kSteps = 8, kBisections = 9;
  static_assert(kDirections % kCoarse == 0);
  second_lines.assign(splats.size(), ClipLine{});
  SurfaceClipStats stats;
  // One pass over a splat: true when it changed only its major axis and is to be measured again.
  const auto fit_once = [&](SplatRecord& s, ClipLine& second, SurfaceClipStats& counts, bool may_shorten) {
    // Measured as drawn, with both axes times the splat scale; the clip lines are in model units
    // (the shaders keep them in place at any scale), the axis factors apply to either size.
    Ellipse e = ellipse_of(s);
    e.a *= scale, e.b *= scale;
    if (!(e.a > 0 && e.b > 0)) return false;
    Surface::Recent recent;
    const auto on_surface = [&](double x, double y) { return surface.within(e.center + x * e.u + y * e.v, tolerance, &recent); };
    const auto rim = [&](int k) {
      const double theta = 2 * std::numbers::pi * k / kDirections;
      return std::array<double, 2>{e.a * std::cos(theta), e.b * std::sin(theta)};
    };
    double reach[kDirections];
    const auto measure = [&](int k) {
      const auto [x, y] = rim(k);
      // March out in steps of 1/kSteps, then bisect between the last point on the surface and the first off it.
      double lo = 0, hi = 1;
      for (int i = 1; i <= kSteps; ++i) {
        const double t = static_cast<double>(i) / kSteps;
        if (!on_surface(t * x, t * y)) {
          hi = t;
          break;
        }
        lo = t;
      }
      if (lo < 1)
        for (int i = 0; i < kBisections; ++i) (on_surface(0.5 * (lo + hi) * x, 0.5 * (lo + hi) * y) ? lo : hi) = 0.5 * (lo + hi);
      reach[k] = lo;
    };
    bool leaves = false;
    for (int k = 0; k < kDirections; k += kDirections / kCoarse) measure(k), leaves = leaves || reach[k] < 1;
    if (!leaves) return false;
    for (int k = 0; k < kDirections; ++k)
      if (k % (kDirections / kCoarse) != 0) measure(k);
    int leaving = 0;
    for (int k = 0; k < kDirections; ++k) leaving += reach[k] < 1;
    // Where no lines keep only the surface, both axes are shrunk to the shortest reach (the
    // splats beside it cover what it gives up).
    const auto shrink = [&] {
      double shortest = 1;
      for (int k = 0; k < kDirections; ++k) shortest = std::min(shortest, reach[k]);
      for (float* c : {&s.major.x, &s.major.y, &s.major.z, &s.minor.x, &s.minor.y, &s.minor.z}) *c = static_cast<float>(*c * shortest);
      ++counts.shrunk;
      return false;
    };
    // A lone direction on the surface between two off it (one that slides along an edge, or through
    // a corner) counts as off: it would split one run in two.
    bool on[kDirections];
    for (int k = 0; k < kDirections; ++k) on[k] = reach[k] >= 1;
    if (kDirections - leaving > 1)
      for (int k = 0; k < kDirections; ++k)
        on[k] = on[k] && !(reach[(k + kDirections - 1) % kDirections] < 1 && reach[(k + 1) % kDirections] < 1);
    std::vector<int> run_starts;
    for (int k = 0; k < kDirections; ++k)
      if (!on[k] && on[(k + kDirections - 1) % kDirections]) run_starts.push_back(k);
    // The surface's end along a run: the last points on it, in order round the rim. A straight
    // edge puts them on one line, a corner on two; a line goes through the innermost of them.
    struct Ends {
      double x[kDirections], y[kDirections];
      std::size_t count = 0;
    };
    const auto ends_of_run = [&](int start) {
      Ends ends;
      for (int i = 0, k = start; i < kDirections && !on[k]; ++i, k = (k + 1) % kDirections) {
        if (reach[k] >= 1) continue;
        const auto [x, y] = rim(k);
        ends.x[ends.count] = reach[k] * x, ends.y[ends.count] = reach[k] * y, ++ends.count;
      }
      return ends;
    };
    // Bisection leaves each end within a/2^(kBisections + 3) of the surface's end along its ray;
    // the tolerance band curves round a corner's tip, up to (1 − 1/√2) of the tolerance off the
    // edges' lines. A line allowed more would lean: a wedge-shaped slit along the edge.
    const double straight = 0.35 * tolerance + std::ldexp(e.a, -(kBisections + 2));
    const auto outward = [](FittedLine line, const double* x, const double* y, std::size_t count) {
      double mx = 0, my = 0;
      for (std::size_t i = 0; i < count; ++i) mx += x[i], my += y[i];
      if (line.nx * mx + line.ny * my < 0) line.nx = -line.nx, line.ny = -line.ny;
      line.offset = INFINITY;
      for (std::size_t i = 0; i < count; ++i) line.offset = std::min(line.offset, line.nx * x[i] + line.ny * y[i]);
      return line;
    };
    const auto one_line = [&](const Ends& ends) {
      if (ends.count == 1) {
        const double l = std::hypot(ends.x[0], ends.y[0]);
        return FittedLine{ends.x[0] / l, ends.y[0] / l, l, 0};
      }
      return outward(fit_line(ends.x, ends.y, ends.count), ends.x, ends.y, ends.count);
    };
    // The kept part's rim and chords must stay on the surface, the lines in front of the centre.
    const double verify_tolerance = 1.05 * tolerance;
    const auto fits = [&](const FittedLine& first, const FittedLine& other) {
      const bool two = std::isfinite(other.residual);
      if (!(first.residual <= straight && first.offset > 0) || (two && !(other.residual <= straight && other.offset > 0))) return false;
      const auto kept = [&](double x, double y) {
        return x * first.nx + y * first.ny <= first.offset && (!two || x * other.nx + y * other.ny <= other.offset);
      };
      for (int k = 0; k < kDirections; ++k) {
        const auto [x, y] = rim(k);
        if (reach[k] < 1 && kept(x, y) && !surface.within(e.center + x * e.u + y * e.v, verify_tolerance, &recent)) return false;
      }
      for (const FittedLine* line : {&first, &other}) {
        if (!std::isfinite(line->residual)) continue;
        // Where the line crosses the ellipse: c + t d, d along the line.
        const double cx = line->nx * line->offset, cy = line->ny * line->offset, dx = -line->ny, dy = line->nx;
        const double ia = 1 / (e.a * e.a), ib = 1 / (e.b * e.b);
        const double qa = dx * dx * ia + dy * dy * ib, qb = 2 * (cx * dx * ia + cy * dy * ib), qc = cx * cx * ia + cy * cy * ib - 1;
        const double disc = qb * qb - 4 * qa * qc;
        if (!(disc > 0)) continue;
        const double t0 = (-qb - std::sqrt(disc)) / (2 * qa), t1 = (-qb + std::sqrt(disc)) / (2 * qa);
        for (int i = 0; i <= 16; ++i) {
          const double t = t0 + (t1 - t0) * i / 16, x = cx + t * dx, y = cy + t * dy;
          if (kept(x * (1 - 1e-9), y * (1 - 1e-9)) && !surface.within(e.center + x * e.u + y * e.v, verify_tolerance, &recent))
            return false;
        }
      }
      return true;
    };
    const auto apply = [&](const FittedLine& first, const FittedLine& other) {
      s.clip_x = static_cast<float>(first.nx), s.clip_y = static_cast<float>(first.ny), s.clip_offset = static_cast<float>(first.offset);
      ++counts.clipped;
      if (std::isfinite(other.residual)) {
        second = {static_cast<float>(other.nx), static_cast<float>(other.ny), static_cast<float>(other.offset)};
        ++counts.cornered;
      }
      return false;
    };
    if (run_starts.size() == 1) {
      // An edge, or a corner: one line, else two, split where their larger residual is least.
      const Ends ends = ends_of_run(run_starts[0]);
      const FittedLine line = one_line(ends);
      if (fits(line, FittedLine{})) return apply(line, FittedLine{});
      double best = INFINITY;
      FittedLine first, other;
      for (std::size_t j = 2; j + 2 <= ends.count; ++j) {
        const FittedLine a = fit_line(ends.x, ends.y, j), b = fit_line(ends.x + j, ends.y + j, ends.count - j);
        if (std::max(a.residual, b.residual) < best) {
          best = std::max(a.residual, b.residual);
          first = outward(a, ends.x, ends.y, j);
          other = outward(b, ends.x + j, ends.y + j, ends.count - j);
        }
      }
      return fits(first, other) ? apply(first, other) : shrink();
    }
    // Two runs whose ends lie on a line each: two edges, each crossed once (a narrow face, or two
    // edges beside a corner the rim passes), a line each. Else the whole rim, or runs on opposite
    // sides: a curved surface under an elongated splat, whose major axis is shortened to the reach
    // along it (never below the minor) and measured again; else the splat is shrunk.
    if (run_starts.size() == 2) {
      const FittedLine first = one_line(ends_of_run(run_starts[0])), other = one_line(ends_of_run(run_starts[1]));
      if (fits(first, other)) return apply(first, other);
    }
    if (may_shorten) {
      double along_u = 1;
      for (int k = 0; k < kDirections; ++k)
        if (std::fabs(std::cos(2 * std::numbers::pi * k / kDirections)) >= std::sqrt(0.5)) along_u = std::min(along_u, reach[k]);
      const double factor = std::max(along_u, e.b / e.a);
      if (factor < 1) {
        for (float* c : {&s.major.x, &s.major.y, &s.major.z}) *c = static_cast<float>(*c * factor);
        ++counts.shortened;
        return true;
      }
    }
    return shrink();
  };
  const auto fit_one = [&](SplatRecord& s, ClipLine& second, SurfaceClipStats& counts) {
    if (std::isfinite(s.clip_offset)) return;
    if (fit_once(s, second, counts, true)) fit_once(s, second, counts, false);
  };
  std::vector<SurfaceClipStats> per_worker(worker_count(splats.size(), 64));
  parallel_for(splats.size(), 64, [&](std::size_t i, std::size_t w) { fit_one(splats[i], second_lines[i], per_worker[w]); });
  for (const SurfaceClipStats& c : per_worker)
    stats.clipped += c.clipped, stats.shortened += c.shortened, stats.cornered += c.cornered, stats.shrunk += c.shrunk;
  return stats;
}

}  // namespace splatcl::splats
