// Cluster bounds and light assignment on the device against the native reference, plus the
// end-to-end guarantee: no light that reaches a pixel is missing from the pixel's cluster list.
#include <gtest/gtest.h>

#include <random>

#include "cluster_fixture.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

using testing::expect_compaction_invariants;
using testing::expect_listed_lights_touch;
using testing::expect_no_false_negatives;
using testing::make_frame;
using testing::Results;
using testing::run_stages;
using testing::test_runtime;

// Every combination of compaction, assignment and shape gives the reference results exactly.
void expect_pipeline_matches_reference(const ClusterConfig& config, const std::vector<float>& depth, DepthFormat format,
                                       const std::vector<PointLight>& lights,
                                       const std::vector<Vec3>* normals = nullptr) {
  const auto layout = ClusterLayout::make(config);
  const auto keys = reference_keys(layout, depth, format, normals);
  const auto clusters = reference_compact(keys);
  const auto bounds = reference_bounds(layout, clusters.unique_keys);
  const auto lists = reference_assign(bounds, lights);
  expect_compaction_invariants(keys, clusters);
  expect_listed_lights_touch(bounds, lights, lists);
  expect_no_false_negatives(layout, depth, format, clusters, lists, lights);

  for (Shape shape : {Shape::Cpu, Shape::Gpu}) {
    ClusterPipeline pipeline(test_runtime(), config, shape);
    pipeline.upload_depth(depth, format);
    if (normals) pipeline.upload_normals(*normals);
    pipeline.upload_lights(lights);
    for (Compaction compaction : {Compaction::GlobalSort, Compaction::TileSort, Compaction::TileBitmask}) {
      for (Assignment assignment : {Assignment::BruteForce, Assignment::Hierarchy}) {
        SCOPED_TRACE(std::string(to_string(compaction)) + ", " + to_string(assignment) + ", shape " + to_string(shape));
        const Results r = run_stages(pipeline, compaction, assignment);
        ASSERT_EQ(r.keys, keys);
        ASSERT_EQ(r.clusters, clusters);
        ASSERT_EQ(r.bounds, bounds);  // same float operations in the same order: bit-exact
        ASSERT_EQ(r.lights, lists);
        EXPECT_EQ(pipeline.light_index_count(), lists.indices.size());
      }
    }
  }
}

TEST(ClusterAssignment, RayCastSceneEveryVariant) {
  const auto frame = make_frame(21, 160, 120);
  expect_pipeline_matches_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, frame.lights);
}

TEST(ClusterAssignment, OddSizesAndSmallTiles) {
  const auto frame = make_frame(22, 100, 37, 16, 8, false, 300);
  expect_pipeline_matches_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, frame.lights);
}

TEST(ClusterAssignment, NormalBitsAndWindowDepth) {
  const auto frame = make_frame(23, 128, 80, 32, 16, true, 150);
  expect_pipeline_matches_reference(frame.config, window_depth(frame.depth, frame.scene.camera), DepthFormat::Window,
                                    frame.lights, &frame.depth.normals);
}

// Every kernel and input variant on a frame small enough for Oclgrind (devices.cluster): window
// depth with normal bits, partial tiles in x and y.
TEST(ClusterAssignment, SmallFrameWindowDepthAndNormalBits) {
  const auto frame = make_frame(40, 40, 21, 16, 8, true, 60);
  expect_pipeline_matches_reference(frame.config, window_depth(frame.depth, frame.scene.camera), DepthFormat::Window,
                                    frame.lights, &frame.depth.normals);
}

TEST(ClusterAssignment, ZeroAndOneLight) {
  const auto frame = make_frame(24, 96, 64);
  expect_pipeline_matches_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, {});
  ASSERT_FALSE(frame.lights.empty());
  expect_pipeline_matches_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, {frame.lights.front()});
}

TEST(ClusterAssignment, EmptyFrameAndOnePixel) {
  const auto frame = make_frame(25, 64, 48);
  expect_pipeline_matches_reference(frame.config, std::vector<float>(64 * 48, kBackgroundViewZ), DepthFormat::ViewZ,
                                    frame.lights);
  ClusterConfig one = frame.config;
  one.width = one.height = 1;
  expect_pipeline_matches_reference(one, {-4.0f}, DepthFormat::ViewZ, {{{0, 0, -4}, 0.5f, {1, 1, 1}}});
}

// Degenerate hierarchies: coincident lights (one Morton cell), zero radii, and a light count that
// leaves partial leaves and nodes.
TEST(ClusterAssignment, DegenerateLights) {
  const auto frame = make_frame(26, 128, 96, 32, 32, false, 0);
  std::vector<PointLight> lights;
  for (int i = 0; i < 77; ++i)
    lights.push_back({{0.5f, -1.0f, -6.0f}, 1.0f + 0.01f * static_cast<float>(i), {1, 0, 0}});
  for (const auto& light : make_frame(26, 128, 96, 32, 32, false, 300).lights)
    lights.push_back({light.center, lights.size() % 3 == 0 ? 0.0f : light.radius, light.color});
  expect_pipeline_matches_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, lights);
}

// Many lights: a deep hierarchy (4 levels) on a larger frame; BVH against brute force only.
TEST(ClusterAssignment, ManyLightsHierarchyMatchesBruteForce) {
  const auto frame = make_frame(27, 320, 240, 32, 32, false, 5000);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  pipeline.upload_lights(frame.lights);
  const Results brute = run_stages(pipeline, Compaction::TileSort, Assignment::BruteForce);
  pipeline.assign_lights(Assignment::Hierarchy);
  const LightLists hierarchy = pipeline.download_light_lists();
  EXPECT_EQ(hierarchy, brute.lights);
  EXPECT_EQ(brute.lights, reference_assign(brute.bounds, frame.lights));
  expect_listed_lights_touch(brute.bounds, frame.lights, hierarchy);
  expect_no_false_negatives(pipeline.layout(), frame.depth.view_z, DepthFormat::ViewZ, brute.clusters, hierarchy,
                            frame.lights);
}

// Over 65536 clusters (noise depth with normal bits, 8×8 tiles) shrink the hierarchy's per-cluster
// list slots to at most 240 entries; 250 lights that reach every cluster then overflow every slot,
// so every list is found again and radix-sorted in place.
TEST(ClusterAssignment, ListsLongerThanTheirSlotsAreFoundAgain) {
  ClusterConfig config;
  config.width = 320;
  config.height = 240;
  config.tile_width = config.tile_height = 8;
  config.near_plane = 0.5f;
  config.far_plane = 60.0f;
  config.normal_bits = true;
  std::mt19937 random(9);
  std::uniform_real_distribution<float> distance(0.5f, 60.0f);
  std::normal_distribution<float> gauss;
  std::vector<float> depth(std::size_t{config.width} * config.height);
  std::vector<Vec3> normals(depth.size());
  for (std::size_t p = 0; p < depth.size(); ++p) {
    depth[p] = p % 29 == 0 ? kBackgroundViewZ : -distance(random);
    normals[p] = normalized(Vec3{gauss(random), gauss(random), gauss(random)});
  }
  ClusterPipeline pipeline(test_runtime(), config);
  pipeline.upload_depth(depth, DepthFormat::ViewZ);
  pipeline.upload_normals(normals);
  pipeline.compute_keys();
  ASSERT_GT(pipeline.compact(Compaction::TileBitmask), 65536u);
  pipeline.compute_bounds();
  const auto bounds = pipeline.download_bounds();
  std::vector<PointLight> lights;
  for (int l = 0; l < 250; ++l)
    lights.push_back({{gauss(random), gauss(random), -30.0f + gauss(random)}, 100.0f, {1, 1, 1}});
  pipeline.upload_lights(lights);
  pipeline.assign_lights(Assignment::Hierarchy);
  const LightLists lists = pipeline.download_light_lists();
  ASSERT_EQ(lists.counts.front(), lights.size());
  EXPECT_EQ(lists, reference_assign(bounds, lights));
}

TEST(ClusterAssignment, BoundsContainEveryPixelOfTheirCluster) {
  const auto frame = make_frame(28, 160, 120, 16, 16);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  pipeline.compute_keys();
  pipeline.compact(Compaction::TileBitmask);
  pipeline.compute_bounds();
  const auto clusters = pipeline.download_clusters();
  const auto bounds = pipeline.download_bounds();
  const auto& layout = pipeline.layout();
  for (std::size_t p = 0; p < frame.depth.view_z.size(); ++p) {
    const auto distance = pixel_distance(layout, frame.depth.view_z[p], DepthFormat::ViewZ);
    if (!distance) continue;
    const auto x = static_cast<std::uint32_t>(p % layout.config.width);
    const auto y = static_cast<std::uint32_t>(p / layout.config.width);
    const Vec3 v = pixel_view_position(layout, x, y, *distance);
    const ClusterBox& box = bounds[clusters.pixel_cluster[p]];
    ASSERT_TRUE(box.min.x <= v.x && v.x <= box.max.x && box.min.y <= v.y && v.y <= box.max.y && box.min.z <= v.z &&
                v.z <= box.max.z)
        << "pixel " << p;
  }
}

TEST(ClusterAssignment, ReusedAcrossFramesAndLightSets) {
  const auto first = make_frame(29, 128, 96, 32, 32, false, 400);
  const auto second = make_frame(30, 128, 96, 32, 32, false, 50);
  ClusterConfig config = first.config;
  config.near_plane = std::min(first.config.near_plane, second.config.near_plane);
  config.far_plane = std::max(first.config.far_plane, second.config.far_plane);
  ClusterPipeline pipeline(test_runtime(), config);
  const auto layout = ClusterLayout::make(config);
  for (const auto* frame : {&first, &second, &first}) {
    pipeline.upload_depth(frame->depth.view_z, DepthFormat::ViewZ);
    pipeline.upload_lights(frame->lights);
    const Results r = run_stages(pipeline, Compaction::TileSort, Assignment::Hierarchy);
    const auto clusters = reference_compact(reference_keys(layout, frame->depth.view_z, DepthFormat::ViewZ));
    ASSERT_EQ(r.clusters, clusters);
    ASSERT_EQ(r.lights, reference_assign(reference_bounds(layout, clusters.unique_keys), frame->lights));
  }
}

TEST(ClusterAssignment, BadLightsAndStageOrderAreErrors) {
  const auto frame = make_frame(31, 64, 48);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  EXPECT_THROW(pipeline.upload_lights({{{0, 0, -1}, -1.0f, {}}}), Error);
  EXPECT_THROW(pipeline.upload_lights({{{0, std::nanf(""), -1}, 1.0f, {}}}), Error);
  pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  pipeline.compute_keys();
  pipeline.compact(Compaction::GlobalSort);
  EXPECT_THROW(pipeline.assign_lights(Assignment::BruteForce), Error);
  EXPECT_THROW(pipeline.download_light_lists(), Error);
  EXPECT_THROW(parse_assignment("octree"), Error);
  EXPECT_EQ(parse_assignment("bvh"), Assignment::Hierarchy);
}

}  // namespace
}  // namespace splatcl::cluster
