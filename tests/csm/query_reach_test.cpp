// The culling geometry of the per-splat lighting (csm/query_reach.hpp): the map slack, an
// instance's placed sphere and reach, the cone of directions that may reach it, the AO kernel's
// directions on the host and a key light's sample points. Host only.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "csm/query_reach.hpp"
#include "csm_test_support.hpp"

namespace splatcl::csm {
namespace {

using testing::translation;

CsmInfo unit_info() {
  CsmInfo info;
  info.resolution = 64;
  info.maps = 1024;
  info.sphere = {{0.5f, 0.0f, 0.0f}, 2.0f};
  return info;
}

TEST(CsmQueryReach, MapSlackIsSmallForSimilaritiesAndPiOtherwise) {
  CsmInfo info = unit_info();
  const float slack = map_slack(info);
  EXPECT_GT(slack, 0.0f);
  EXPECT_LT(slack, 0.5f);  // 1024 maps: neighbours a few degrees apart, the pole rows' cells wider
  info.object_transform = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1};  // uniform scale keeps angles
  EXPECT_FLOAT_EQ(map_slack(info), slack);
  info.object_transform = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // a stretch does not
  EXPECT_EQ(map_slack(info), std::numbers::pi_v<float>);
  CsmInfo fewer = unit_info();
  fewer.maps = 64;
  EXPECT_GT(map_slack(fewer), slack);
}

TEST(CsmQueryReach, ReachIsTheSpherePlacedPlusThePcfMargin) {
  const CsmInfo info = unit_info();
  const MovedReach reach = moved_reach(info, translation(3, 4, 5), 0.1f);
  EXPECT_NEAR(reach.centre.x, 3.5f, 1e-5f);
  EXPECT_NEAR(reach.centre.y, 4.0f, 1e-5f);
  EXPECT_NEAR(reach.centre.z, 5.0f, 1e-5f);
  const double texel = 2.0 * 2.0 / 64;
  EXPECT_NEAR(reach.radius, 2.0 * 1.0001, 1e-5);
  EXPECT_NEAR(reach.reach, (2.0 + kReachTexels * texel) * 1.0001, 1e-5);
  EXPECT_GE(kReachTexels * texel, 2.5 * std::sqrt(2.0) * texel);  // the 4 × 4 PCF footprint
  EXPECT_FLOAT_EQ(reach.cos_slack, std::cos(0.1f));
}

TEST(CsmQueryReach, ConeHoldsTheDirectionsTowardsTheSphereWithinTheSlack) {
  const CsmInfo info = unit_info();
  const float slack = 0.05f;
  const MovedReach reach = moved_reach(info, translation(-0.5, 0, 0), slack);  // sphere at the origin
  EXPECT_TRUE(reach.cone_from({0.5f, 0.5f, 0.0f}).always);  // inside the sphere
  const glm::vec3 p(0.0f, 0.0f, 20.0f);
  const Cone cone = reach.cone_from(p);
  ASSERT_FALSE(cone.always);
  const auto reaches = [&](glm::vec3 w) { return cone.may_reach(w, glm::length(w)); };
  EXPECT_TRUE(reaches({0, 0, -1}));   // straight at the centre
  EXPECT_FALSE(reaches({0, 0, 1}));   // away from it
  EXPECT_FALSE(reaches({1, 0, 0}));   // sideways
  // The cone's half angle is asin(R'/d) + slack: just inside reaches, just outside does not.
  const float half = std::asin(reach.reach / 20.0f) + slack;
  EXPECT_TRUE(reaches({std::sin(half - 0.01f), 0, -std::cos(half - 0.01f)}));
  EXPECT_FALSE(reaches({std::sin(half + 0.01f), 0, -std::cos(half + 0.01f)}));
  // A slack of π/2 or more: every direction within π of the centre's.
  EXPECT_TRUE(moved_reach(info, translation(-0.5, 0, 0), std::numbers::pi_v<float>).cone_from(p).always);
}

TEST(CsmQueryReach, AoDirectionsLieOnTheNormalsHemisphereAndTheFloorCutsThem) {
  // Patterns are hemispheres about +y, reflected onto the normal's.
  const std::vector<Vec4> pattern = {{0, 1, 0, 0}, {0.6f, 0.8f, 0, 0}, {0, 0.8f, 0.6f, 0}, {-0.8f, 0.6f, 0, 0}};
  const Vec4 normal{1, 0, 0, 0};
  Vec4 out[4];
  ao_directions(normal, pattern.data(), 4, false, out);
  for (const Vec4& d : out) {
    const float length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    EXPECT_NEAR(length, 1.0f, 1e-5f);
    EXPECT_EQ(d.w, length);
    EXPECT_GT(d.x, 0.0f);  // above the receiver's surface
  }
  EXPECT_NEAR(out[0].x, 1.0f, 1e-6f);  // the pattern's pole goes to the normal
  EXPECT_LT(out[3].y, 0.0f);           // (0.6, -0.8, 0): below the floor
  ao_directions(normal, pattern.data(), 4, true, out);
  for (const Vec4& d : out) EXPECT_EQ(d.w == 0.0f, d.y < 0.0f);
  EXPECT_EQ(out[3].w, 0.0f);
}

TEST(CsmQueryReach, KeyLightPointsAreItsCentreOrSpreadOnItsSphere) {
  const std::vector<glm::vec3> point = key_light_points({{1, 2, 3}, 0.0f}, 8);
  ASSERT_EQ(point.size(), 1u);
  EXPECT_EQ(point[0], glm::vec3(1, 2, 3));
  const std::vector<glm::vec3> points = key_light_points({{1, 2, 3}, 0.5f}, 16);
  ASSERT_EQ(points.size(), 16u);
  glm::vec3 mean(0.0f);
  for (const glm::vec3& p : points) {
    EXPECT_NEAR(glm::length(p - glm::vec3(1, 2, 3)), 0.5f, 1e-5f);
    mean += p / 16.0f;
  }
  EXPECT_LT(glm::length(mean - glm::vec3(1, 2, 3)), 0.05f);
}

}  // namespace
}  // namespace splatcl::csm
