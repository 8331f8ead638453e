#include "csm/query_reach.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "csm/sphere_grid.hpp"

namespace splatcl::csm {

// Visibility of a key light from each receiver: PCF queries towards the light's centre, or for a
// light of non-zero size the mean over `samples` points spread on its sphere (Fibonacci lattice),
// which softens the shadow edge.
std::vector<glm::vec3> key_light_points(const KeyLightShape& light, std::uint32_t samples) {
  const std::uint32_t count = light.size > 0 ? std::max(1u, samples) : 1u;
  std::vector<glm::vec3> points;
  for (std::uint32_t j = 0; j < count; ++j) {
    glm::vec3 p = light.position;
    if (count > 1) {
      const float y = 1.0f - 2.0f * (static_cast<float>(j) + 0.5f) / static_cast<float>(count);
      const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
      const float phi = static_cast<float>(j) * 2.39996323f;  // golden angle
      p += light.size * glm::vec3(r * std::cos(phi), y, r * std::sin(phi));
    }
    points.push_back(p);
  }
  return points;
}

std::vector<float> key_light_visibility(csm::VisibilityQueries& queries, const std::vector<Vec4>& receivers,
                                        const KeyLightShape& light, std::uint32_t samples, Filter filter, float bias) {
  const std::vector<glm::vec3> light_points = key_light_points(light, samples);
  // One batch for all the light's points (point-major: each point's run of receivers stays as
  // coherent as on its own), so one launch per instance instead of one per instance and point.
  const std::size_t n = receivers.size();
  std::vector<Vec4> batch, points;
  batch.reserve(n * light_points.size());
  points.reserve(n * light_points.size());
  for (const glm::vec3& p : light_points) {
    batch.insert(batch.end(), receivers.begin(), receivers.end());
    points.insert(points.end(), n, Vec4{p.x, p.y, p.z, 1.0f});
  }
  const std::vector<float> visible = queries.run(batch, points, filter, bias);
  std::vector<float> sum(n, 0.0f);
  for (std::size_t j = 0; j < light_points.size(); ++j)
    for (std::size_t i = 0; i < n; ++i) sum[i] += visible[j * n + i];
  for (float& v : sum) v /= static_cast<float>(light_points.size());
  return sum;
}

Cone MovedReach::cone_from(glm::vec3 p) const {
  Cone cone;
  cone.to_centre = centre - p;
  const float d2 = glm::dot(cone.to_centre, cone.to_centre);
  // Behind the sphere within the line's reach (the second case above), or inside it.
  if (d2 <= radius * radius + reach * reach) return cone.always = true, cone;
  cone.distance = std::sqrt(d2);
  const float sin_reach = std::min(1.0f, reach / cone.distance);  // of the angle R' subtends from p
  if (slack < 0.5f * std::numbers::pi_v<float>) {
    // cos(asin(sin_reach) + slack) without trigonometric calls (both angles below π/2, their sum
    // below π); its rounding is far inside the margins of R' and the slack.
    cone.cos_limit = std::sqrt(1.0f - sin_reach * sin_reach) * cos_slack - sin_reach * sin_slack;
    return cone;
  }
  const float limit = std::asin(sin_reach) + slack;
  if (limit >= std::numbers::pi_v<float>) return cone.always = true, cone;
  cone.cos_limit = std::cos(limit);
  return cone;
}

// The largest angle between a direction and the map chosen for it, bounded by the largest angle
// between a map's direction and its grid neighbours' (rows clamped, columns wrapped) and, for the
// first and last rows, the pole; times 1.25 for float rounding. Angles carry over to the world
// only through a similarity: any other object transform gets π (every query is made).
float map_slack(const CsmInfo& info) {
  const auto& t = info.object_transform;
  const glm::vec3 x(t[0], t[4], t[8]), y(t[1], t[5], t[9]), z(t[2], t[6], t[10]);
  const float scale = glm::length(x), tolerance = 1e-4f * scale;
  if (!(scale > 0) || std::abs(glm::length(y) - scale) > tolerance || std::abs(glm::length(z) - scale) > tolerance ||
      std::abs(glm::dot(x, y)) > tolerance * scale || std::abs(glm::dot(y, z)) > tolerance * scale ||
      std::abs(glm::dot(x, z)) > tolerance * scale)
    return std::numbers::pi_v<float>;
  const csm::SphereGrid grid(info.distribution, info.order, info.pole, info.maps);
  const auto direction = [&](std::uint32_t a, std::uint32_t b) {
    const csm::Camera c = grid.camera(grid.sequence_of({a, b}));
    return glm::normalize(glm::vec3(c.d[0], c.d[1], c.d[2]));
  };
  const auto pole = csm::pole_frame(info.pole)[1];
  const glm::vec3 up = glm::normalize(glm::vec3(pole.x, pole.y, pole.z));
  const auto angle = [](glm::vec3 a, glm::vec3 b) { return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)); };
  const std::uint32_t rows = grid.rows(), cols = grid.cols();
  float slack = 0;
  for (std::uint32_t a = 0; a < rows; ++a)
    for (std::uint32_t b = 0; b < cols; ++b) {
      const glm::vec3 d = direction(a, b);
      for (int da = -1; da <= 1; ++da)
        for (int db = -1; db <= 1; ++db) {
          const int na = std::clamp(static_cast<int>(a) + da, 0, static_cast<int>(rows) - 1);
          const int nb = ((static_cast<int>(b) + db) % static_cast<int>(cols) + static_cast<int>(cols)) % static_cast<int>(cols);
          slack = std::max(slack, angle(d, direction(static_cast<std::uint32_t>(na), static_cast<std::uint32_t>(nb))));
        }
      if (a == 0 || a + 1 == rows) slack = std::max(slack, std::min(angle(d, up), angle(d, -up)));
    }
  return 1.25f * slack;
}

namespace {

// Object space (the maps') → world for `info` placed by `placement`, and the largest stretch of its
// linear part (rigid placements: the uniform scale).
glm::dmat4 object_to_world(const CsmInfo& info, const Transform& placement, double& stretch) {
  const Transform to_object = world_to_object(info, placement);
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = to_object[static_cast<std::size_t>(4 * r + c)];
  const glm::dmat4 to_world = glm::inverse(m);
  stretch = 0;
  for (int k = 0; k < 3; ++k) stretch = std::max(stretch, glm::length(glm::dvec3(to_world[k])));
  return to_world;
}

}  // namespace

float placed_texel(const CsmInfo& info, const Transform& placement) {
  double stretch = 0;
  object_to_world(info, placement, stretch);
  return static_cast<float>(stretch * 2.0 * info.sphere.radius / std::max(1u, info.resolution));
}

// The bounding sphere of `info` placed by `placement` (model file → world), and its reach R'.
MovedReach moved_reach(const CsmInfo& info, const Transform& placement, float slack, double reach_texels) {
  double stretch = 0;
  const glm::dmat4 to_world = object_to_world(info, placement, stretch);
  const glm::dvec3 c(info.sphere.centre.x, info.sphere.centre.y, info.sphere.centre.z);
  MovedReach reach;
  reach.centre = glm::vec3(to_world * glm::dvec4(c, 1.0));
  const double texel = 2.0 * info.sphere.radius / std::max(1u, info.resolution);
  reach.radius = static_cast<float>(stretch * info.sphere.radius * 1.0001);
  reach.reach = static_cast<float>(stretch * (info.sphere.radius + reach_texels * texel) * 1.0001);
  reach.slack = slack;
  reach.cos_slack = std::cos(slack);
  reach.sin_slack = std::sin(slack);
  return reach;
}

// The AO kernel's query directions for receiver normal n into out[0 .. samples) (the rotation
// functions of kernels/csm_query.h, and neither side contracts them, so the vectors are
// bit-identical); w = |d| for the Cone tests, or 0 for a direction below the floor, which the kernel
// counts as occluded without a query.
void ao_directions(const Vec4& n, const Vec4* pattern, std::uint32_t samples, bool ground, Vec4* out) {
  float h[3];
  csm::device::csm_ao_rotation_axis(n.x, n.y, n.z, h);
  for (std::uint32_t k = 0; k < samples; ++k) {
    float d[3];
    csm::device::csm_ao_rotate(h, pattern[k].x, pattern[k].y, pattern[k].z, d);
    out[k] = {d[0], d[1], d[2], ground && d[1] < 0.0f ? 0.0f : glm::length(glm::vec3(d[0], d[1], d[2]))};
  }
}

}  // namespace splatcl::csm
