#pragma once
// The mesh surface as the truth that splats are checked against: its triangles (each polygon
// fan-triangulated from its first corner, so a non-planar polygon is the triangles its corners
// span, not a plane), exact point-to-surface distances in double through a box tree, and
// area-uniform random points for independent checks.
#include <cmath>
#include <cstdint>
#include <vector>

#include "math/dvec3.hpp"
#include "core/mesh.hpp"

namespace splatcl::splats {

// An axis-aligned box tree over items given by their boxes (median split on the longest axis,
// leaves of at most 4 items). Queries visit the items of every leaf whose box lies within a radius
// of a point (so every item whose own box does, and some more), nearest leaves first; the visitor
// may shrink the radius (nearest-item searches) or stop the walk.
class BoxTree {
 public:
  struct Box {
    DVec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    void add(DVec3 p);
    void add(const Box& b);
    // Euclidean distance from p to the box (0 inside), and its square.
    double distance(DVec3 p) const { return std::sqrt(distance2(p)); }
    double distance2(DVec3 p) const {
      const double dx = p.x < lo.x ? lo.x - p.x : p.x > hi.x ? p.x - hi.x : 0.0;
      const double dy = p.y < lo.y ? lo.y - p.y : p.y > hi.y ? p.y - hi.y : 0.0;
      const double dz = p.z < lo.z ? lo.z - p.z : p.z > hi.z ? p.z - hi.z : 0.0;
      return dx * dx + dy * dy + dz * dz;
    }
  };

  BoxTree() = default;
  explicit BoxTree(const std::vector<Box>& boxes);

  // visit(item, radius) -> bool: called for each item of each leaf within `radius` of p (leaves in
  // near-first order) below node `start` (0: the root, the whole tree); it may lower `radius`;
  // returning true ends the walk.
  template <class Visit>
  void visit(DVec3 p, double& radius, Visit&& visit, std::uint32_t start = 0) const {
    if (nodes_.empty() || !(radius >= 0)) return;
    struct Entry {
      std::uint32_t node;
      double distance2;
    };
    Entry stack[128];
    int top = 0;
    const double root2 = nodes_[start].box.distance2(p);
    if (root2 > radius * radius) return;
    stack[top++] = {start, root2};
    while (top > 0) {
      const Entry entry = stack[--top];
      if (entry.distance2 > radius * radius) continue;  // the radius shrank since it was pushed
      const Node& node = nodes_[entry.node];
      if (node.count > 0) {
        for (std::uint32_t r = node.first; r < node.first + node.count; ++r)
          if (visit(items_[r], radius)) return;
        continue;
      }
      const std::uint32_t a = node.first, b = node.first + 1;
      const double da = nodes_[a].box.distance2(p), db = nodes_[b].box.distance2(p);
      const double limit = radius * radius;
      // The nearer child is popped first.
      if (da <= db) {
        if (db <= limit) stack[top++] = {b, db};
        if (da <= limit) stack[top++] = {a, da};
      } else {
        if (da <= limit) stack[top++] = {a, da};
        if (db <= limit) stack[top++] = {b, db};
      }
    }
  }

  // visit() below `start`, then below each sibling on the way up to the root: every item once,
  // the subtrees around `start` first, without walking down from the root again.
  template <class Visit>
  void visit_outward(DVec3 p, double& radius, Visit&& visit, std::uint32_t start) const {
    bool stopped = false;
    const auto watch = [&](std::uint32_t item, double& r) { return stopped = visit(item, r); };
    this->visit(p, radius, watch, start);
    for (std::uint32_t node = start; !stopped && node != 0; node = parents_[node]) {
      const std::uint32_t first = nodes_[parents_[node]].first;
      this->visit(p, radius, watch, node == first ? first + 1 : first);
    }
  }

  std::size_t size() const { return items_.size(); }
  // The node `levels` above the leaf that holds `item` (the root at most): a region around the
  // item that a run of nearby queries can search before the whole tree.
  std::uint32_t ancestor(std::uint32_t item, int levels) const;

 private:
  struct Node {
    Box box;
    std::uint32_t first = 0, count = 0;  // leaf: items_[first, first + count); inner: children first, first + 1
  };
  void build(std::uint32_t index, const std::vector<Box>& boxes, std::uint32_t begin, std::uint32_t end, int depth);
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> parents_;  // per node (the root's is itself)
  std::vector<std::uint32_t> items_;
  std::vector<std::uint32_t> leaf_of_;  // per item
};

struct SurfaceTriangle {
  DVec3 a, b, c;
  DVec3 normal;  // unit, by the corners' winding
  DVec3 centroid;
  double reach = 0;  // the farthest corner's distance from the centroid
  double area = 0;
  std::uint32_t face = 0;              // mesh face it belongs to
  std::uint32_t corners[3] = {0, 0, 0};  // mesh corner indices (into Mesh::corners) of a, b, c
};

// The closest point of triangle t to p (Ericson, Real-Time Collision Detection §5.1.5, in double).
DVec3 closest_point(const SurfaceTriangle& t, DVec3 p);

// Barycentric weights (of a, b, c) of p projected into t's plane; (1, 0, 0) for a degenerate t.
struct Barycentric {
  double a = 1, b = 0, c = 0;
};
Barycentric barycentric(const SurfaceTriangle& t, DVec3 p);

// The fan triangles of every face, without those of zero or non-finite area.
std::vector<SurfaceTriangle> surface_triangles(const Mesh& mesh);

class Surface {
 public:
  explicit Surface(const Mesh& mesh);

  const std::vector<SurfaceTriangle>& triangles() const { return triangles_; }
  double area() const { return area_; }

  struct Nearest {
    double distance = INFINITY;
    std::uint32_t triangle = UINT32_MAX;  // UINT32_MAX when nothing lies within the limit
  };
  struct Recent;
  // The nearest triangle to p among those within `limit` (ties to the lowest index). `recent`, as
  // for within(), only speeds the search up.
  Nearest nearest(DVec3 p, double limit = INFINITY, Recent* recent = nullptr) const;
  // The triangles that answered the last queries of a run of nearby points, most recent first,
  // and the tree region around the last one.
  struct Recent {
    static constexpr int kSize = 4;
    std::uint32_t triangles[kSize] = {UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX};
    std::uint32_t pieces[kSize] = {0, 0, 0, 0};  // the tree item (a piece of the triangle) each was found by
    std::uint32_t region = 0;  // a tree node; 0, the root, until a query answers
    void remember(std::uint32_t t, std::uint32_t piece);
  };
  // Whether some triangle lies within `radius` of p (stops at the first one found). `recent`, when
  // given, is tried first (its triangles, then the tree outward from its region) and updated.
  // `facing`, when given, counts only triangles whose plane is within its angle of its normal
  // (either side, or with `same_side` only triangles that face its way).
  struct Facing {
    DVec3 normal;    // unit
    double min_cos;  // |normal · triangle normal| at least this (normal · triangle normal with same_side)
    bool same_side = false;
  };
  bool within(DVec3 p, double radius, Recent* recent = nullptr, const Facing* facing = nullptr) const;

  struct Point {
    DVec3 position, normal;
    std::uint32_t triangle = 0;
  };
  // `count` points uniformly distributed over the surface area, from `seed` (the same points on
  // every platform: a SplitMix64 stream, no standard-library distributions).
  std::vector<Point> uniform_points(std::size_t count, std::uint64_t seed) const;

 private:
  std::vector<SurfaceTriangle> triangles_;
  std::vector<double> cumulative_area_;
  double area_ = 0;
  BoxTree tree_;  // over pieces of the triangles (a needle's slices), not whole triangles
  std::vector<std::uint32_t> piece_triangle_;  // per tree item
};

// SplitMix64: a small, portable, seedable stream of 64-bit values and uniform doubles in [0, 1).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

}  // namespace splatcl::splats
