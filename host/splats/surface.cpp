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
    if (mesh.zero_area_face(f)) continue;  // its normal is noise: gap splats laid on it stood across the surface
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

namespace {
// The most slices a needle's box is cut into, and the aspect (length over base) of each slice.
constexpr double kMaxSlices = 64;
constexpr double kSliceAspect = 4;

// Boxes covering triangle (a, b, c), appended to `boxes`. A needle's (or a cap's) own box is mostly
// empty, and the boxes of a fan of needles all overlap near its centre: every query there walked
// to hundreds of triangles (a disc of 1,500 needles: 175 per nearest(), against 10 for a disc of
// well-shaped triangles). A cap is split at its longest edge's midpoint into two needles; a needle
// is cut across, towards its apex, into slices about kSliceAspect times as long as its base.
void add_piece_boxes(DVec3 a, DVec3 b, DVec3 c, int depth, std::vector<BoxTree::Box>& boxes) {
  const DVec3 p[3] = {a, b, c};
  const double l2[3] = {dot(b - c, b - c), dot(c - a, c - a), dot(a - b, a - b)};  // opposite p[k]
  const int lo = l2[0] <= l2[1] && l2[0] <= l2[2] ? 0 : l2[1] <= l2[2] ? 1 : 2;
  const int hi = l2[0] >= l2[1] && l2[0] >= l2[2] ? 0 : l2[1] >= l2[2] ? 1 : 2;
  const DVec3 n = cross(b - a, c - a);
  if (depth < 2 && lo != hi && 4 * l2[lo] >= std::min(l2[(lo + 1) % 3], l2[(lo + 2) % 3]) && l2[hi] * l2[hi] > 16 * dot(n, n)) {
    const DVec3 mid = 0.5 * (p[(hi + 1) % 3] + p[(hi + 2) % 3]);
    add_piece_boxes(p[hi], p[(hi + 1) % 3], mid, depth + 1, boxes);
    add_piece_boxes(p[hi], mid, p[(hi + 2) % 3], depth + 1, boxes);
    return;
  }
  const DVec3 o = p[lo], u = p[(lo + 1) % 3] - o, v = p[(lo + 2) % 3] - o;
  const double base = std::sqrt(l2[lo]), side = std::sqrt(std::max(l2[(lo + 1) % 3], l2[(lo + 2) % 3]));
  const double slices = base > 0 ? std::clamp(std::ceil(side / (kSliceAspect * base)), 1.0, kMaxSlices) : 1.0;
  const int count = static_cast<int>(slices);
  // Widened by a rounding margin, so the slices' boxes hold every point of the triangle: the
  // slices' corners round relative to their coordinates' magnitude as well as the needle's size.
  const double magnitude = std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)});
  const DVec3 margin = (1e-12 * (side + magnitude)) * DVec3{1, 1, 1};
  for (int k = 0; k < count; ++k) {
    const double f0 = k / slices, f1 = (k + 1) / slices;
    BoxTree::Box box;
    box.add(o + f0 * u), box.add(o + f0 * v);
    if (k + 1 < count) box.add(o + f1 * u), box.add(o + f1 * v);
    else box.add(p[(lo + 1) % 3]), box.add(p[(lo + 2) % 3]);
    box.add(box.lo - margin), box.add(box.hi + margin);
    boxes.push_back(box);
  }
}
}  // namespace

Surface::Surface(const Mesh& mesh) : triangles_(surface_triangles(mesh)) {
  std::vector<BoxTree::Box> boxes;
  boxes.reserve(triangles_.size());
  cumulative_area_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    add_piece_boxes(triangles_[t].a, triangles_[t].b, triangles_[t].c, 0, boxes);
    piece_triangle_.resize(boxes.size(), static_cast<std::uint32_t>(t));
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
  std::uint32_t best_piece = 0;
  double radius = limit;
  const auto consider = [&](std::uint32_t piece, double& r) {
    const std::uint32_t t = piece_triangle_[piece];
    // A triangle of several pieces answers once (its distance does not change).
    if (t == best.triangle) return false;
    const SurfaceTriangle& tri = triangles_[t];
    // Farther than r from the plane or from the corners' ball is farther from the triangle: no
    // closest point needed.
    if (std::fabs(dot(p - tri.a, tri.normal)) > r || beyond_reach(tri, p, r)) return false;
    const double d = length(closest_point(tri, p) - p);
    if (d <= r && (d < best.distance || (d == best.distance && t < best.triangle))) {
      best = {d, t};
      best_piece = piece;
      r = d;
    }
    return false;
  };
  if (recent) {
    // The recent triangles and the region bound the radius, so the walk from the root prunes
    // nearly everything.
    for (std::size_t k = 0; k < Recent::kSize; ++k)
      if (recent->triangles[k] < triangles_.size()) consider(recent->pieces[k], radius);
  }
  // From the region outward: the region's triangles are not measured twice.
  tree_.visit_outward(p, radius, consider, recent ? recent->region : 0);
  if (recent && best.triangle != UINT32_MAX) {
    recent->remember(best.triangle, best_piece);
    recent->region = tree_.ancestor(best_piece, kRegionLevels);
  }
  return best;
}

void Surface::Recent::remember(std::uint32_t t, std::uint32_t piece) {
  int k = 0;
  while (k + 1 < kSize && triangles[k] != t) ++k;
  for (; k > 0; --k) triangles[k] = triangles[k - 1], pieces[k] = pieces[k - 1];
  triangles[0] = t, pieces[0] = piece;
}

bool Surface::within(DVec3 p, double radius, Recent* recent, const Facing* facing) const {
  const auto near = [&](const SurfaceTriangle& tri) {
    if (std::fabs(dot(p - tri.a, tri.normal)) > radius || beyond_reach(tri, p, radius)) return false;
    if (facing) {
      const double c = dot(facing->normal, tri.normal);
      if ((facing->same_side ? c : std::fabs(c)) < facing->min_cos) return false;
    }
    const DVec3 d = closest_point(tri, p) - p;
    return dot(d, d) <= radius * radius;
  };
  std::uint32_t answer = UINT32_MAX;
  const auto search = [&](std::uint32_t start) {
    double r = radius;
    tree_.visit_outward(p, r, [&](std::uint32_t piece, double&) { return near(triangles_[piece_triangle_[piece]]) && (answer = piece, true); }, start);
    return answer != UINT32_MAX;
  };
  if (!recent) return search(0);
  for (int k = 0; k < Recent::kSize; ++k) {
    const std::uint32_t t = recent->triangles[k];
    if (t >= triangles_.size()) break;
    if (!near(triangles_[t])) continue;
    recent->remember(t, recent->pieces[k]);
    return true;
  }
  // The region first (a query near the last one is mostly answered there, a few levels down), then
  // outward from it.
  if (!search(recent->region)) return false;
  recent->remember(piece_triangle_[answer], answer);
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
