#include "splats/surface.hpp"

#include <algorithm>
#include <numeric>

namespace splatcl::splats {

void BoxTree::Box::add(DVec3 p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

void BoxTree::Box::add(const Box& b) {
  add(b.lo);
  add(b.hi);
}

BoxTree::BoxTree(const std::vector<Box>& boxes) {
  if (boxes.empty()) return;
  items_.resize(boxes.size());
  std::iota(items_.begin(), items_.end(), 0u);
  leaf_of_.resize(boxes.size());
  nodes_.reserve(boxes.size() / 2 + 2);
  nodes_.emplace_back();
  parents_.push_back(0);
  build(0, boxes, 0, static_cast<std::uint32_t>(boxes.size()), 0);
}

void BoxTree::build(std::uint32_t index, const std::vector<Box>& boxes, std::uint32_t begin, std::uint32_t end, int depth) {
  Box bounds, centres;
  for (std::uint32_t r = begin; r < end; ++r) {
    const Box& b = boxes[items_[r]];
    bounds.add(b);
    centres.add(0.5 * (b.lo + b.hi));
  }
  nodes_[index].box = bounds;
  const DVec3 extent = centres.hi - centres.lo;
  // Median splits halve the range, so the depth (and the traversal stack) stays near log2(n).
  if (end - begin <= 4 || depth >= 60 || !(std::max({extent.x, extent.y, extent.z}) > 0)) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    for (std::uint32_t r = begin; r < end; ++r) leaf_of_[items_[r]] = index;
    return;
  }
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const auto centre = [&](std::uint32_t item) {
    const Box& b = boxes[item];
    return axis == 0 ? b.lo.x + b.hi.x : axis == 1 ? b.lo.y + b.hi.y : b.lo.z + b.hi.z;
  };
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + middle, items_.begin() + end, [&](std::uint32_t a, std::uint32_t b) {
    const double ca = centre(a), cb = centre(b);
    return ca < cb || (ca == cb && a < b);
  });
  const std::uint32_t children = static_cast<std::uint32_t>(nodes_.size());
  nodes_[index].first = children;
  nodes_[index].count = 0;
  nodes_.emplace_back();
  nodes_.emplace_back();
  parents_.push_back(index);
  parents_.push_back(index);
  build(children, boxes, begin, middle, depth + 1);
  build(children + 1, boxes, middle, end, depth + 1);
}

std::uint32_t BoxTree::ancestor(std::uint32_t item, int levels) const {
  std::uint32_t node = leaf_of_[item];
  for (int k = 0; k < levels && node != 0; ++k) node = parents_[node];
  return node;
}

Barycentric barycentric(const SurfaceTriangle& t, DVec3 p) {
  const DVec3 e1 = t.b - t.a, e2 = t.c - t.a, w = p - t.a;
  const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), dw1 = dot(w, e1), dw2 = dot(w, e2);
  const double den = d11 * d22 - d12 * d12;
  const double s = den != 0 ? (d22 * dw1 - d12 * dw2) / den : 0, r = den != 0 ? (d11 * dw2 - d12 * dw1) / den : 0;
  return {1 - s - r, s, r};
}

DVec3 closest_point(const SurfaceTriangle& t, DVec3 p) {
  const DVec3 ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return t.a;
  const DVec3 bp = p - t.b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return t.b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return t.a + (d1 / (d1 - d3)) * ab;
  const DVec3 cp = p - t.c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return t.c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return t.a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return t.b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (t.c - t.b);
  const double denom = 1.0 / (va + vb + vc);
  return t.a + (vb * denom) * ab + (vc * denom) * ac;
}

std::vector<SurfaceTriangle> surface_triangles(const Mesh& mesh) {
  std::vector<SurfaceTriangle> out;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t c = begin + 1; c + 1 < end; ++c) {
      SurfaceTriangle t;
      t.a = DVec3(mesh.vertices[mesh.corners[begin]]);
      t.b = DVec3(mesh.vertices[mesh.corners[c]]);
      t.c = DVec3(mesh.vertices[mesh.corners[c + 1]]);
      const DVec3 n = cross(t.b - t.a, t.c - t.a);
      t.area = 0.5 * length(n);
      if (!(t.area > 0) || !std::isfinite(t.area)) continue;
      t.normal = normalized(n);
      t.centroid = (1.0 / 3.0) * (t.a + t.b + t.c);
      t.reach = std::sqrt(std::max({dot(t.a - t.centroid, t.a - t.centroid), dot(t.b - t.centroid, t.b - t.centroid),
                                    dot(t.c - t.centroid, t.c - t.centroid)}));
      t.face = static_cast<std::uint32_t>(f);
      t.corners[0] = begin, t.corners[1] = c, t.corners[2] = c + 1;
      out.push_back(t);
    }
  }
  return out;
}

Surface::Surface(const Mesh& mesh) : triangles_(surface_triangles(mesh)) {
  std::vector<BoxTree::Box> boxes(triangles_.size());
  cumulative_area_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    boxes[t].add(triangles_[t].a), boxes[t].add(triangles_[t].b), boxes[t].add(triangles_[t].c);
    area_ += triangles_[t].area;
    cumulative_area_[t] = area_;
  }
  tree_ = BoxTree(boxes);
}

namespace {
// How far above the answer's leaf a Recent's region lies: 2^4 leaves of up to 4 triangles.
constexpr int kRegionLevels = 4;

// Whether p lies farther than r from every point of the ball of the triangle's corners (and so
// from the triangle), with a margin that leaves the rounding of the exact distance to decide ties.
bool beyond_reach(const SurfaceTriangle& t, DVec3 p, double r) {
  const DVec3 w = p - t.centroid;
  const double reach = (t.reach + r) * (1 + 1e-9);
  return dot(w, w) > reach * reach;
}
}  // namespace

Surface::Nearest Surface::nearest(DVec3 p, double limit, Recent* recent) const {
  Nearest best;
  double radius = limit;
  const auto consider = [&](std::uint32_t t, double& r) {
    const SurfaceTriangle& tri = triangles_[t];
    // Farther than r from the plane or from the corners' ball is farther from the triangle: no
    // closest point needed.
    if (std::fabs(dot(p - tri.a, tri.normal)) > r || beyond_reach(tri, p, r)) return false;
    const double d = length(closest_point(tri, p) - p);
    if (d <= r && (d < best.distance || (d == best.distance && t < best.triangle))) {
      best = {d, t};
      r = d;
    }
    return false;
  };
  if (recent) {
    // The recent triangles and the region bound the radius, so the walk from the root prunes
    // nearly everything.
    for (const std::uint32_t t : recent->triangles)
      if (t < triangles_.size()) consider(t, radius);
  }
  // From the region outward: the region's triangles are not measured twice.
  tree_.visit_outward(p, radius, consider, recent ? recent->region : 0);
  if (recent && best.triangle != UINT32_MAX) {
    recent->remember(best.triangle);
    recent->region = tree_.ancestor(best.triangle, kRegionLevels);
  }
  return best;
}

void Surface::Recent::remember(std::uint32_t t) {
  int k = 0;
  while (k + 1 < kSize && triangles[k] != t) ++k;
  for (; k > 0; --k) triangles[k] = triangles[k - 1];
  triangles[0] = t;
}

bool Surface::within(DVec3 p, double radius, Recent* recent) const {
  const auto near = [&](const SurfaceTriangle& tri) {
    if (std::fabs(dot(p - tri.a, tri.normal)) > radius || beyond_reach(tri, p, radius)) return false;
    const DVec3 d = closest_point(tri, p) - p;
    return dot(d, d) <= radius * radius;
  };
  std::uint32_t answer = UINT32_MAX;
  const auto search = [&](std::uint32_t start) {
    double r = radius;
    tree_.visit_outward(p, r, [&](std::uint32_t t, double&) { return near(triangles_[t]) && (answer = t, true); }, start);
    return answer != UINT32_MAX;
  };
  if (!recent) return search(0);
  for (const std::uint32_t t : recent->triangles) {
    if (t >= triangles_.size()) break;
    if (!near(triangles_[t])) continue;
    recent->remember(t);
    return true;
  }
  // The region first (a query near the last one is mostly answered there, a few levels down), then
  // outward from it.
  if (!search(recent->region)) return false;
  recent->remember(answer);
  recent->region = tree_.ancestor(answer, kRegionLevels);
  return true;
}

std::vector<Surface::Point> Surface::uniform_points(std::size_t count, std::uint64_t seed) const {
  std::vector<Point> points;
  if (triangles_.empty() || !(area_ > 0)) return points;
  points.reserve(count);
  SplitMix64 random{seed};
  for (std::size_t i = 0; i < count; ++i) {
    const double pick = random.uniform() * area_;
    const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), pick);
    const std::uint32_t t = static_cast<std::uint32_t>(std::min<std::size_t>(it - cumulative_area_.begin(), triangles_.size() - 1));
    const SurfaceTriangle& tri = triangles_[t];
    // Uniform in the triangle: the square-root warp of two uniforms.
    const double r1 = std::sqrt(random.uniform()), r2 = random.uniform();
    const DVec3 p = (1 - r1) * tri.a + (r1 * (1 - r2)) * tri.b + (r1 * r2) * tri.c;
    points.push_back({p, tri.normal, t});
  }
  return points;
}

}  // namespace splatcl::splats
