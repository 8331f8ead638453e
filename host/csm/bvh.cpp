#include "csm/bvh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "runtime/error.hpp"

namespace splatcl::csm {
namespace {

struct Bounds {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void add(const float p[3]) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::fmin(lo[k], p[k]);
      hi[k] = std::fmax(hi[k], p[k]);
    }
  }
  void add(const Bounds& b) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::fmin(lo[k], b.lo[k]);
      hi[k] = std::fmax(hi[k], b.hi[k]);
    }
  }
  float area() const {
    if (lo[0] > hi[0]) return 0;
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return x * y + y * z + z * x;
  }
};

struct Item {
  Bounds bounds;
  float centre[3];
};

constexpr int kBins = 16;
constexpr std::uint32_t kLeafSize = 4;

class Builder {
 public:
  Builder(std::vector<BvhTriangle>& triangles) : triangles_(triangles) {
    items_.resize(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const BvhTriangle& t = triangles[i];
      float p1[3], p2[3];
      for (int k = 0; k < 3; ++k) {
        p1[k] = t.v0[k] + t.e1[k];
        p2[k] = t.v0[k] + t.e2[k];
      }
      Item& item = items_[i];
      item.bounds.add(t.v0);
      item.bounds.add(p1);
      item.bounds.add(p2);
      for (int k = 0; k < 3; ++k) item.centre[k] = 0.5f * (item.bounds.lo[k] + item.bounds.hi[k]);
    }
    order_.resize(triangles.size());
    std::iota(order_.begin(), order_.end(), 0u);
  }

  Bvh build() {
    Bvh bvh;
    nodes_.reserve(2 * items_.size());
    bvh.depth = node(0, static_cast<std::uint32_t>(items_.size()), 1);
    bvh.nodes = std::move(nodes_);
    bvh.triangles.reserve(order_.size());
    for (std::uint32_t i : order_) bvh.triangles.push_back(triangles_[i]);
    return bvh;
  }

 private:
  // Builds the subtree over order_[begin, end) and returns its depth.
  std::uint32_t node(std::uint32_t begin, std::uint32_t end, std::uint32_t depth) {
    const std::uint32_t self = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    Bounds bounds, centres;
    for (std::uint32_t i = begin; i < end; ++i) {
      bounds.add(items_[order_[i]].bounds);
      centres.add(items_[order_[i]].centre);
    }
    auto make_leaf = [&] {
      BvhNode& n = nodes_[self];
      std::copy(bounds.lo, bounds.lo + 3, n.lo);
      std::copy(bounds.hi, bounds.hi + 3, n.hi);
      n.index = begin;
      n.count = end - begin;
      return depth;
    };
    const std::uint32_t count = end - begin;
    if (count <= kLeafSize || depth >= kBvhMaxDepth) return make_leaf();

    // Best binned split over the three axes by centroid.
    float best_cost = INFINITY;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float extent = centres.hi[axis] - centres.lo[axis];
      if (!(extent > 0)) continue;
      std::array<Bounds, kBins> bin_bounds;
      std::array<std::uint32_t, kBins> bin_counts{};
      const float scale = kBins / extent;
      for (std::uint32_t i = begin; i < end; ++i) {
        const Item& item = items_[order_[i]];
        const int b = std::min(kBins - 1, static_cast<int>((item.centre[axis] - centres.lo[axis]) * scale));
        bin_bounds[static_cast<std::size_t>(b)].add(item.bounds);
        ++bin_counts[static_cast<std::size_t>(b)];
      }
      std::array<float, kBins> right_area{};
      std::array<std::uint32_t, kBins> right_count{};
      Bounds acc;
      std::uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.add(bin_bounds[static_cast<std::size_t>(b)]);
        n += bin_counts[static_cast<std::size_t>(b)];
        right_area[static_cast<std::size_t>(b)] = acc.area();
        right_count[static_cast<std::size_t>(b)] = n;
      }
      Bounds left;
      std::uint32_t left_count = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        left.add(bin_bounds[static_cast<std::size_t>(b)]);
        left_count += bin_counts[static_cast<std::size_t>(b)];
        const std::uint32_t rc = right_count[static_cast<std::size_t>(b + 1)];
        if (left_count == 0 || rc == 0) continue;
        const float cost = left.area() * static_cast<float>(left_count) + right_area[static_cast<std::size_t>(b + 1)] * static_cast<float>(rc);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }
    // SAH with a traversal cost of one triangle test: split only when it pays.
    if (best_axis < 0 || best_cost >= (static_cast<float>(count) - 1.0f) * bounds.area()) {
      if (count <= 4 * kLeafSize || best_axis < 0) return make_leaf();
    }
    std::uint32_t mid = begin;
    if (best_axis >= 0) {
      const float extent = centres.hi[best_axis] - centres.lo[best_axis];
      const float scale = kBins / extent;
      const float lo = centres.lo[best_axis];
      const int axis = best_axis, bin = best_bin;
      auto* split = std::partition(order_.data() + begin, order_.data() + end, [&](std::uint32_t i) {
        return std::min(kBins - 1, static_cast<int>((items_[i].centre[axis] - lo) * scale)) <= bin;
      });
      mid = static_cast<std::uint32_t>(split - order_.data());
    }
    if (mid == begin || mid == end) {
      mid = begin + count / 2;  // identical centroids: split by count
      std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                       [&](std::uint32_t x, std::uint32_t y) { return x < y; });
    }
    const std::uint32_t left_depth = node(begin, mid, depth + 1);
    const std::uint32_t right = static_cast<std::uint32_t>(nodes_.size());
    const std::uint32_t right_depth = node(mid, end, depth + 1);
    BvhNode& n = nodes_[self];
    std::copy(bounds.lo, bounds.lo + 3, n.lo);
    std::copy(bounds.hi, bounds.hi + 3, n.hi);
    n.index = right;
    n.count = 0;
    return std::max(left_depth, right_depth);
  }

  std::vector<BvhTriangle>& triangles_;
  std::vector<Item> items_;
  std::vector<std::uint32_t> order_;
  std::vector<BvhNode> nodes_;
};

// Plain comparisons (minss/maxss) instead of fmin/fmax: inverse directions are finite, so no NaN.
inline float min2(float a, float b) { return a < b ? a : b; }
inline float max2(float a, float b) { return a > b ? a : b; }

// Entry distance of the ray into the node's box, or INFINITY when it misses or enters beyond `limit`.
float box_entry(const BvhNode& n, const float o[3], const float inv[3], float limit) {
  const float ax = (n.lo[0] - o[0]) * inv[0], bx = (n.hi[0] - o[0]) * inv[0];
  const float ay = (n.lo[1] - o[1]) * inv[1], by = (n.hi[1] - o[1]) * inv[1];
  const float az = (n.lo[2] - o[2]) * inv[2], bz = (n.hi[2] - o[2]) * inv[2];
  const float tmin = max2(max2(min2(ax, bx), min2(ay, by)), min2(az, bz));
  const float tmax = min2(min2(max2(ax, bx), max2(ay, by)), max2(az, bz));
  return (tmin <= tmax && tmax >= 0.0f && tmin <= limit) ? tmin : INFINITY;
}

// Depth-first traversal, nearer child first, skipping nodes that start beyond limit(); the same
// walk as csm_first_two_hits in kernels/csm_trace.h. visit(first, count) handles a leaf and returns
// false to stop.
template <class Limit, class Visit>
void traverse(const Bvh& bvh, const float o[3], const float inv[3], Limit limit, Visit visit) {
  if (bvh.nodes.empty() || box_entry(bvh.nodes[0], o, inv, limit()) == INFINITY) return;
  std::uint32_t stack_node[kBvhMaxDepth];
  float stack_entry[kBvhMaxDepth];
  int sp = 0;
  std::uint32_t node = 0;
  for (;;) {
    const BvhNode& n = bvh.nodes[node];
    bool descend = false;
    if (n.count > 0) {
      if (!visit(n.index, n.count)) return;
    } else {
      const std::uint32_t left = node + 1, right = n.index;
      const float el = box_entry(bvh.nodes[left], o, inv, limit()), er = box_entry(bvh.nodes[right], o, inv, limit());
      if (el != INFINITY && er != INFINITY) {
        const bool left_first = el <= er;
        stack_node[sp] = left_first ? right : left;
        stack_entry[sp] = left_first ? er : el;
        ++sp;
        node = left_first ? left : right;
        descend = true;
      } else if (el != INFINITY) {
        node = left;
        descend = true;
      } else if (er != INFINITY) {
        node = right;
        descend = true;
      }
    }
    if (descend) continue;
    bool found = false;
    while (sp > 0) {
      --sp;
      if (stack_entry[sp] <= limit()) {
        node = stack_node[sp];
        found = true;
        break;
      }
    }
    if (!found) return;
  }
}

}  // namespace

void relative_position(const splats::Mesh& mesh, std::uint32_t v, Vec3 origin, float out[3]) {
  const Vec3 p = mesh.vertices[v];
  out[0] = static_cast<float>(static_cast<double>(p.x) - origin.x);
  out[1] = static_cast<float>(static_cast<double>(p.y) - origin.y);
  out[2] = static_cast<float>(static_cast<double>(p.z) - origin.z);
}

std::vector<std::uint32_t> casting_triangles(const splats::Mesh& mesh, Vec3 origin) {
  std::vector<std::uint32_t> triangles;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t first = mesh.face_offsets[f], last = mesh.face_offsets[f + 1];
    for (std::uint32_t c = first + 1; c + 1 < last; ++c) {
      const std::uint32_t v[3] = {mesh.corners[first], mesh.corners[c], mesh.corners[c + 1]};
      float p[3][3];
      for (int k = 0; k < 3; ++k) relative_position(mesh, v[k], origin, p[k]);
      const Vec3 e1{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
      const Vec3 e2{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
      const Vec3 n = cross(e1, e2);
      if (!(dot(n, n) > 0)) continue;
      triangles.insert(triangles.end(), v, v + 3);
    }
  }
  if (triangles.empty()) throw Error(mesh.source + ": every face is degenerate (zero area), nothing casts a shadow");
  return triangles;
}

std::vector<BvhTriangle> mesh_triangles(const splats::Mesh& mesh, Vec3 origin) {
  const std::vector<std::uint32_t> corners = casting_triangles(mesh, origin);
  std::vector<BvhTriangle> triangles(corners.size() / 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    BvhTriangle& tri = triangles[t];
    float p1[3], p2[3];
    relative_position(mesh, corners[3 * t], origin, tri.v0);
    relative_position(mesh, corners[3 * t + 1], origin, p1);
    relative_position(mesh, corners[3 * t + 2], origin, p2);
    for (int k = 0; k < 3; ++k) {
      tri.e1[k] = p1[k] - tri.v0[k];
      tri.e2[k] = p2[k] - tri.v0[k];
    }
  }
  return triangles;
}

Bvh build_bvh(std::vector<BvhTriangle> triangles) {
  if (triangles.empty()) return {};
  return Builder(triangles).build();
}

float triangle_hit(const BvhTriangle& tri, const float o[3], const float dir[3]) {
  const float* e1 = tri.e1;
  const float* e2 = tri.e2;
  const float px = dir[1] * e2[2] - dir[2] * e2[1], py = dir[2] * e2[0] - dir[0] * e2[2], pz = dir[0] * e2[1] - dir[1] * e2[0];
  const float det = e1[0] * px + e1[1] * py + e1[2] * pz;
  if (det == 0.0f) return INFINITY;
  const float inv_det = 1.0f / det;
  const float tx = o[0] - tri.v0[0], ty = o[1] - tri.v0[1], tz = o[2] - tri.v0[2];
  const float u = (tx * px + ty * py + tz * pz) * inv_det;
  if (u < 0.0f || u > 1.0f) return INFINITY;
  const float qx = ty * e1[2] - tz * e1[1], qy = tz * e1[0] - tx * e1[2], qz = tx * e1[1] - ty * e1[0];
  const float v = (dir[0] * qx + dir[1] * qy + dir[2] * qz) * inv_det;
  if (v < 0.0f || u + v > 1.0f) return INFINITY;
  const float t = (e2[0] * qx + e2[1] * qy + e2[2] * qz) * inv_det;
  return t > 0.0f ? t : INFINITY;
}

TwoHits first_two_hits(const Bvh& bvh, const float o[3], const float dir[3], const float inv[3], float eps) {
  TwoHits hits{INFINITY, INFINITY};
  traverse(bvh, o, inv, [&] { return hits.t2; },
           [&](std::uint32_t first, std::uint32_t count) {
             for (std::uint32_t k = first; k < first + count; ++k) {
               const float t = triangle_hit(bvh.triangles[k], o, dir);
               if (t < hits.t1 - eps) {
                 hits.t2 = hits.t1;
                 hits.t1 = t;
               } else if (t <= hits.t1 + eps) {
                 hits.t1 = std::fmin(hits.t1, t);
               } else if (t < hits.t2) {
                 hits.t2 = t;
               }
             }
             return true;
           });
  return hits;
}

float inverse_direction(float d) {
  // A finite stand-in for 1/0 keeps the box tests free of 0 × inf = NaN.
  return d == 0.0f ? 1e30f : 1.0f / d;
}

bool any_hit(const Bvh& bvh, const float o[3], const float dir[3], float t_max) {
  const float inv[3] = {inverse_direction(dir[0]), inverse_direction(dir[1]), inverse_direction(dir[2])};
  bool hit = false;
  traverse(bvh, o, inv, [&] { return t_max; },
           [&](std::uint32_t first, std::uint32_t count) {
             for (std::uint32_t k = first; k < first + count; ++k)
               if (triangle_hit(bvh.triangles[k], o, dir) < t_max) {
                 hit = true;
                 return false;
               }
             return true;
           });
  return hit;
}

}  // namespace splatcl::csm
