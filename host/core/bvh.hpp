#pragma once
// A bounding volume hierarchy over a mesh's triangles, built on the host with the binned surface
// area heuristic, flattened depth-first so the OpenCL kernels (kernels/csm_trace.h) and the native
// traversal here walk the same nodes in the same order with the same float operations.
//
// Coordinates are relative to an origin (a bounding sphere's centre, a camera's eye) to keep float
// error small. Core holds it because the CSM capture and the scene ray caster (core/scene_ray_cast.hpp)
// both trace it.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"
#include "core/mesh.hpp"

namespace splatcl {

// The node, triangle and traversal of kernels/csm_trace.h, shared with the capture kernel.
namespace device_trace {
using uint = std::uint32_t;
#include "../../kernels/csm_trace.h"
}  // namespace device_trace

// Internal node: count == 0, children at (this + 1) and `index`. Leaf: triangles [index, index + count).
using BvhNode = device_trace::CsmNode;
// A triangle as vertex 0 and the two edges from it, precomputed once so both traversals use the
// same values.
using BvhTriangle = device_trace::CsmTriangle;

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<BvhTriangle> triangles;
  std::uint32_t depth = 0;  // longest root-to-leaf path (the traversal stack needs fewer entries)
};

// Maximum tree depth; the traversal stack has this many entries.
inline constexpr std::uint32_t kBvhMaxDepth = CSM_MAX_DEPTH;

// Vertex v relative to `origin` as both capture methods see it: the float of the double difference.
void relative_position(const Mesh& mesh, std::uint32_t v, Vec3 origin, float out[3]);

// The triangles that cast shadows, for both capture methods: the mesh's faces fan-triangulated
// from their first corner, without those whose float edge cross product relative to `origin` is
// zero. Vertex index triples, flat. Throws Error naming the mesh when none remains.
std::vector<std::uint32_t> casting_triangles(const Mesh& mesh, Vec3 origin);

// The length unit a scene of bounding radius `radius` is traced in: 2^ilogb(radius), so the tracer
// sees a radius in [1, 2). In the model's own units the ray-triangle distance's numerator (∝ R ·
// |edge|²) overflows float from R ≈ 1e13 and underflows near 1e-14; dividing by a power of two is
// exact, so hits are bit-identical wherever those units worked.
inline float trace_unit(float radius) { return std::ldexp(1.0f, std::ilogb(radius)); }

// casting_triangles as positions relative to `origin` (a vertex and two edges each), in units of
// `unit` (trace_unit).
std::vector<BvhTriangle> mesh_triangles(const Mesh& mesh, Vec3 origin, float unit = 1.0f);

// Binned SAH build; leaves hold at most 4 triangles.
Bvh build_bvh(std::vector<BvhTriangle> triangles);

// Nearest and next distinct hit distance along o + t·dir (t > 0); a hit within `eps` of the
// nearest counts as the same surface (shared edges and vertices). INFINITY where there is none.
struct TwoHits {
  float t1, t2;
};
TwoHits first_two_hits(const Bvh& bvh, const float o[3], const float dir[3], const float inv[3], float eps);

// The nearest triangle hit along o + t·dir (t > 0) and its index in bvh.triangles, t = INFINITY on
// a miss: what a primary ray needs (the hit triangle gives the normal). `edge_tolerance` widens
// each triangle's barycentric bounds (csm_triangle_hit_within): 0 tests as the capture does.
struct ClosestHit {
  float t = INFINITY;
  std::uint32_t triangle = 0;
};
ClosestHit closest_hit(const Bvh& bvh, const float o[3], const float dir[3], const float inv[3], float edge_tolerance = 0.0f);

// Whether any triangle is hit at 0 < t < t_max (exact visibility for ground truth).
bool any_hit(const Bvh& bvh, const float o[3], const float dir[3], float t_max);

// 1 / d, or 1e30 for d = 0, so that box tests never compute 0 × inf. Capture and query use it for
// every inverse direction they pass to the traversal.
float inverse_direction(float d);

// Ray-triangle distance (Möller–Trumbore, edges inclusive), INFINITY on a miss (csm_triangle_hit).
float triangle_hit(const BvhTriangle& tri, const float o[3], const float dir[3]);

}  // namespace splatcl
