#pragma once
// Which CSM queries of the per-splat lighting can answer "occluded", and the queries' shapes: the
// geometry that lets an update skip the queries through an occluder instance that cannot reach a
// receiver (the presenter's incremental lighting), the AO kernel's query directions on the host,
// and the points sampled on a key light of non-zero size.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "csm/csm_file.hpp"
#include "csm/visibility.hpp"
#include "core/mesh.hpp"

namespace splatcl::csm {

// R' − R in texels of the map: at least the PCF footprint's reach, 2.5·√2 ≈ 3.54 texels (4 × 4
// taps, kernels/csm_query.h, around the receiver's projection), rounded up.
inline constexpr double kReachTexels = 5.0;
static_assert(kReachTexels >= 2.5 * 1.41421357);

// Culling the per-splat lighting queries. A CSM query through one occluder instance (csm_query.h) is 1
// exactly unless one of its taps reads a non-empty texel with a stored depth in front of the
// receiver. Non-empty texels have their centres inside the disc of the bounding sphere's radius R;
// taps (4 × 4 PCF at most) lie within 2.5·√2 texels of the receiver's projection; stored depths are
// >= 0 and the bias >= 0, so an occluded receiver lies behind the plane at R from the centre,
// towards the map's direction d. Hence, with R' = R + kReachTexels texels: the receiver p can be occluded
// through map d only if its distance to the line (centre, d) is <= R' and (p − centre)·d < R. The
// map a query picks lies within `slack` radians of the query's direction w, so if no direction
// within `slack` of w can satisfy both, the instance answers 1 for (p, w) at that placement.
// The reach R' − R, in texels, that makes Cone bound the queries of `filter` with a bias of `bias`
// texels; none where no reach does. None and SameMap: kReachTexels for any bias >= 0 (the proof
// above). CrossMap taps 4 maps, an unbounded slack: none. March follows the light ray itself in
// each map it asks and answers "occluded" only where the ray's biased depth passes a texel's stored
// depth inside that texel, or lies between two neighbouring texels' depths (behind the one it
// leaves, in front of the one it enters) on their shared face. A stored depth lies on its texel's
// chord through the bounding sphere, so that point of the ray lies within √2/2 texel sideways of a
// point in the sphere, and the real ray bias texels behind it: within R + (0.71 + bias) texels of
// the centre, and w points from p within asin(R' / |centre − p|) of the centre, with no map slack,
// for R' − R >= 0.71 + bias texels (1.5 + bias leaves room for rounding).
inline std::optional<double> cone_reach_texels(Filter filter, float bias) {
  if (!(bias >= 0)) return std::nullopt;
  if (filter == Filter::None || filter == Filter::SameMap) return kReachTexels;
  if (filter == Filter::March) return std::max(kReachTexels, 1.5 + static_cast<double>(bias));
  return std::nullopt;
}

struct Cone {
  bool always = false;   // p too close to the sphere: every direction may reach it
  glm::vec3 to_centre{}; // centre − p
  float distance = 0;    // |centre − p|
  float cos_limit = 0;   // w may reach iff cos∠(w, centre − p) >= cos_limit
  // w_length = |w|, computed once per direction for all the cones.
  bool may_reach(glm::vec3 w, float w_length) const {
    return always || glm::dot(w, to_centre) >= cos_limit * w_length * distance;
  }
};

struct MovedReach {
  glm::vec3 centre{};        // bounding sphere, world space
  float radius = 0, reach = 0, slack = 0;
  float cos_slack = 1, sin_slack = 0;
  // The cone of directions from p through which this instance may answer "occluded".
  Cone cone_from(glm::vec3 p) const;
};

// The largest angle between a direction and the map chosen for it (the slack of MovedReach), from
// the CSM's sphere grid; π for an object transform that is not a similarity.
float map_slack(const CsmInfo& info);

// The bounding sphere of `info` placed by `placement` (model file → world, row-major) and its reach
// R' = R + `reach_texels` texels (cone_reach_texels), for the map slack `slack`.
MovedReach moved_reach(const CsmInfo& info, const Transform& placement, float slack, double reach_texels = kReachTexels);

// The world size of one texel of `info`'s maps placed by `placement` (model file → world): the
// largest stretch of the placement times 2R / resolution.
float placed_texel(const CsmInfo& info, const Transform& placement);

// How far receivers on an occluder's own surface are lifted along their normal, in texels of its
// CSM (placed_texel), so that its maps do not shadow it where the depth sampled at a texel's centre
// lies in front of the receiver (acne). A planar surface through the receiver p with normal n is in
// front of p + δn, seen along a map's direction d at an offset e ⟂ d from it, only where
// n·e < −δ, and |n·e| ≤ |e| at any angle between n and d: so δ ≥ the farthest tap centre suffices
// at every slope, unlike a depth bias, which grows as tan of that angle. AO queries read one texel
// (centre within √2/2 texel), the 4 × 4 PCF of the shadows reaches centres within 2√2 texels.
inline constexpr float kAoLiftTexels = 1.0f;
inline constexpr float kShadowLiftTexels = 2.9f;
static_assert(kAoLiftTexels >= 0.7072f && kShadowLiftTexels >= 2.8285f);

// The AO kernel's query directions for receiver normal n into out[0 .. samples), bit-identical to
// the kernel's (kernels/csm_query.h's rotation functions, neither side contracted); w = |d|, or 0
// for a direction below the floor (`ground`), which the kernel counts as occluded without a query.
void ao_directions(const Vec4& n, const Vec4* pattern, std::uint32_t samples, bool ground, Vec4* out);

// A key light as the shadow queries see it: its centre and the radius of its spherical emitter.
struct KeyLightShape {
  glm::vec3 position{0.0f};
  float size = 0.0f;  // 0: a point
};

// The points a key light's visibility is averaged over: its centre, or for a light of non-zero size
// `samples` points on its sphere (Fibonacci lattice), which softens the shadow edge.
std::vector<glm::vec3> key_light_points(const KeyLightShape& light, std::uint32_t samples);

// Visibility of a key light from each receiver: the mean over key_light_points of the PCF queries
// through the instances placed in `queries`, in one batch.
std::vector<float> key_light_visibility(VisibilityQueries& queries, const std::vector<Vec4>& receivers,
                                        const KeyLightShape& light, std::uint32_t samples, Filter filter, float bias);

}  // namespace splatcl::csm
