// Host shading: clustered light lists lose nothing, so shading with them equals shading with every
// light, bit for bit (same formula, lights summed in the same ascending order, culled ones add 0).
#include <gtest/gtest.h>

#include <numeric>

#include "cluster/shading.hpp"
#include "cluster_fixture.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

using testing::make_frame;
using testing::test_runtime;

TEST(ClusterShading, FalloffIsOneAtTheLightAndExactlyZeroFromTheRadiusOn) {
  EXPECT_EQ(light_falloff(0.0f, 2.0f), 1.0f);
  EXPECT_FLOAT_EQ(light_falloff(1.0f, 2.0f), 0.75f);
  EXPECT_EQ(light_falloff(2.0f, 2.0f), 0.0f);
  EXPECT_EQ(light_falloff(5.0f, 2.0f), 0.0f);
  EXPECT_EQ(light_falloff(0.0f, 0.0f), 0.0f);
}

TEST(ClusterShading, ClusteredEqualsBruteForceExactly) {
  for (const bool normal_bits : {false, true}) {
    const auto frame = make_frame(31, 200, 150, 32, 32, normal_bits, 400);
    ClusterPipeline pipeline(test_runtime(), frame.config);
    pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
    if (normal_bits) pipeline.upload_normals(frame.depth.normals);
    pipeline.upload_lights(frame.lights);
    pipeline.compute_keys();
    pipeline.compact(Compaction::TileSort);
    pipeline.compute_bounds();
    pipeline.assign_lights(Assignment::Hierarchy);
    const Vec3 albedo{0.8f, 0.6f, 0.4f};
    const auto clustered = shade_clustered(pipeline.layout(), frame.depth.view_z, frame.depth.normals, frame.lights,
                                           pipeline.download_clusters(), pipeline.download_light_lists(), albedo);
    const auto brute = shade_brute_force(pipeline.layout(), frame.depth.view_z, frame.depth.normals, frame.lights, albedo);
    EXPECT_EQ(clustered, brute);
    // The frame is actually lit, so the equality says something.
    std::size_t lit = 0;
    for (float v : brute) lit += v > 0.0f;
    EXPECT_GT(lit, brute.size() / 20);
  }
}

TEST(ClusterShading, BackgroundStaysBlackAndSizesAreChecked) {
  const auto frame = make_frame(32, 64, 48);
  const auto layout = ClusterLayout::make(frame.config);
  const auto rgb = shade_brute_force(layout, frame.depth.view_z, frame.depth.normals, frame.lights, {1, 1, 1});
  for (std::size_t p = 0; p < layout.pixel_count(); ++p)
    if (frame.depth.view_z[p] == kBackgroundViewZ) {
      EXPECT_EQ(rgb[3 * p], 0.0f);
    }
  EXPECT_THROW(shade_brute_force(layout, {}, frame.depth.normals, frame.lights, {1, 1, 1}), Error);
}

// `cluster --lights 300000` checked silently for 28 s: the brute-force shading reports its rows,
// one call at a time, counting up to the frame's rows, and the image does not change.
TEST(ClusterShading, BruteForceReportsItsRowsWithoutChangingTheImage) {
  const auto frame = make_frame(200, 64, 48);
  const auto layout = ClusterLayout::make(frame.config);
  std::vector<std::size_t> reported;
  const auto with_progress = shade_brute_force(layout, frame.depth.view_z, frame.depth.normals, frame.lights, {1, 1, 1},
                                               [&](std::size_t done, std::size_t rows) {
                                                 EXPECT_EQ(rows, 48u);
                                                 reported.push_back(done);
                                               });
  std::vector<std::size_t> every_row(48);
  std::iota(every_row.begin(), every_row.end(), std::size_t{1});
  EXPECT_EQ(reported, every_row);
  EXPECT_EQ(with_progress, shade_brute_force(layout, frame.depth.view_z, frame.depth.normals, frame.lights, {1, 1, 1}));
}

}  // namespace
}  // namespace splatcl::cluster
