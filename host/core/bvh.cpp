#include "core/bvh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "runtime/error.hpp"

namespace splatcl {
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
      const float scale = kBins / extent;
      // A denormal extent gives an infinite scale, and 0 x inf a NaN bin (an index far out of the
      // bins: a splat object fitted around one huge Gaussian crashed here).
      if (!(extent > 0) || !std::isfinite(scale)) continue;
      std::array<Bounds, kBins> bin_bounds;
      std::array<std::uint32_t, kBins> bin_counts{};
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

}  // namespace

void relative_position(const Mesh& mesh, std::uint32_t v, Vec3 origin, float out[3]) {
  const Vec3 p = mesh.vertices[v];
  out[0] = static_cast<float>(static_cast<double>(p.x) - origin.x);
  out[1] = static_cast<float>(static_cast<double>(p.y) - origin.y);
  out[2] = static_cast<float>(static_cast<double>(p.z) - origin.z);
}

std::vector<std::uint32_t> casting_triangles(const Mesh& mesh, Vec3 origin) {
  std::vector<std::uint32_t> triangles;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t first = mesh.face_offsets[f], last = mesh.face_offsets[f + 1];
    for (std::uint32_t c = first + 1; c + 1 < last; ++c) {
      const std::uint32_t v[3] = {mesh.corners[first], mesh.corners[c], mesh.corners[c + 1]};
      float p[3][3];
      for (int k = 0; k < 3; ++k) relative_position(mesh, v[k], origin, p[k]);
      // The float edges' cross product in double: in float, |n|² underflows to 0 for edges below
      // ~1e-10 and a tiny mesh lost its triangles (a torus scaled by 3e-11 had "every face degenerate").
      double e1[3], e2[3];
      for (int k = 0; k < 3; ++k) e1[k] = double{p[1][k] - p[0][k]}, e2[k] = double{p[2][k] - p[0][k]};
      const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      if (!(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0)) continue;
      triangles.insert(triangles.end(), v, v + 3);
    }
  }
  if (triangles.empty()) throw Error(mesh.source + ": every face is degenerate (zero area), nothing casts a shadow");
  return triangles;
}

std::vector<BvhTriangle> mesh_triangles(const Mesh& mesh, Vec3 origin, float unit) {
  const std::vector<std::uint32_t> corners = casting_triangles(mesh, origin);
  std::vector<BvhTriangle> triangles(corners.size() / 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    BvhTriangle& tri = triangles[t];
    float p1[3], p2[3];
    relative_position(mesh, corners[3 * t], origin, tri.v0);
    relative_position(mesh, corners[3 * t + 1], origin, p1);
    relative_position(mesh, corners[3 * t + 2], origin, p2);
    for (int k = 0; k < 3; ++k) {
      tri.e1[k] = (p1[k] - tri.v0[k]) / unit;
      tri.e2[k] = (p2[k] - tri.v0[k]) / unit;
      tri.v0[k] /= unit;
    }
  }
  return triangles;
}

Bvh build_bvh(std::vector<BvhTriangle> triangles) {
  if (triangles.empty()) return {};
  return Builder(triangles).build();
}

float triangle_hit(const BvhTriangle& tri, const float o[3], const float dir[3]) {
  return device_trace::csm_triangle_hit(&tri, o, dir);
}

TwoHits first_two_hits(const Bvh& bvh, const float o[3], const float dir[3], const float inv[3], float eps) {
  if (bvh.nodes.empty()) return {INFINITY, INFINITY};
  const device_trace::CsmHits hits =
      device_trace::csm_trace(bvh.nodes.data(), bvh.triangles.data(), o, dir, inv, eps, CSM_TRACE_FIRST_TWO, INFINITY);
  return {hits.t1, hits.t2};
}

float inverse_direction(float d) {
  // A finite stand-in for 1/0 keeps the box tests free of 0 × inf = NaN.
  return d == 0.0f ? 1e30f : 1.0f / d;
}

ClosestHit closest_hit(const Bvh& bvh, const float o[3], const float dir[3], const float inv[3], float edge_tolerance) {
  ClosestHit best;
  if (bvh.nodes.empty()) return best;
  std::uint32_t stack[kBvhMaxDepth + 2];
  std::uint32_t top = 0;
  stack[top++] = 0;
  while (top) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    float t0 = 0, t1 = best.t;
    for (int k = 0; k < 3; ++k) {
      float a = (node.lo[k] - o[k]) * inv[k], b = (node.hi[k] - o[k]) * inv[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (t0 > t1) continue;
    if (node.count == 0) {
      const auto self = static_cast<std::uint32_t>(&node - bvh.nodes.data());
      stack[top++] = node.index;
      stack[top++] = self + 1;
      continue;
    }
    for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
      const float t = device_trace::csm_triangle_hit_within(&bvh.triangles[k], o, dir, edge_tolerance);
      if (t > 0 && t < best.t) best = {t, k};
    }
  }
  return best;
}

bool any_hit(const Bvh& bvh, const float o[3], const float dir[3], float t_max) {
  if (bvh.nodes.empty()) return false;
  const float inv[3] = {inverse_direction(dir[0]), inverse_direction(dir[1]), inverse_direction(dir[2])};
  const device_trace::CsmHits hits =
      device_trace::csm_trace(bvh.nodes.data(), bvh.triangles.data(), o, dir, inv, 0.0f, CSM_TRACE_ANY, t_max);
  return hits.t1 < t_max;
}

}  // namespace splatcl
