// Cluster keys and the three compaction variants on the device against the native reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <string>

#include "cluster_fixture.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

using testing::expect_compaction_invariants;
using testing::make_frame;
using testing::test_runtime;

constexpr Compaction kCompactions[] = {Compaction::GlobalSort, Compaction::TileSort, Compaction::TileBitmask};

// Runs keys and every compaction variant in both shapes; everything must equal the reference.
void expect_all_variants_match_reference(const ClusterConfig& config, const std::vector<float>& depth,
                                         DepthFormat format, const std::vector<Vec3>* normals = nullptr,
                                         std::initializer_list<Shape> shapes = {Shape::Cpu, Shape::Gpu}) {
  const auto layout = ClusterLayout::make(config);
  const auto keys = reference_keys(layout, depth, format, normals);
  const auto expected = reference_compact(keys);
  expect_compaction_invariants(keys, expected);
  for (Shape shape : shapes) {
    ClusterPipeline pipeline(test_runtime(), config, shape);
    pipeline.upload_depth(depth, format);
    if (normals) pipeline.upload_normals(*normals);
    pipeline.compute_keys();
    ASSERT_EQ(pipeline.download_keys(), keys) << "shape " << to_string(shape);
    for (Compaction compaction : kCompactions) {
      SCOPED_TRACE(std::string(to_string(compaction)) + ", shape " + to_string(shape));
      EXPECT_EQ(pipeline.compact(compaction), expected.unique_keys.size());
      const ClusterList clusters = pipeline.download_clusters();
      ASSERT_EQ(clusters.unique_keys, expected.unique_keys);
      ASSERT_EQ(clusters.pixel_cluster, expected.pixel_cluster);
    }
  }
}

TEST(ClusterKeys, RayCastSceneAllVariantsBothShapes) {
  const auto frame = make_frame(11, 160, 120);
  expect_all_variants_match_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ);
}

TEST(ClusterKeys, SizesNotMultipleOfTheTile) {
  const auto frame = make_frame(12, 100, 37, 16, 8);
  expect_all_variants_match_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ);
}

TEST(ClusterKeys, NormalBitVariant) {
  const auto frame = make_frame(13, 128, 96, 32, 32, true);
  expect_all_variants_match_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, &frame.depth.normals);
}

TEST(ClusterKeys, WindowDepthInput) {
  const auto frame = make_frame(14, 120, 90, 16, 16);
  const auto window = window_depth(frame.depth, frame.scene.camera);
  expect_all_variants_match_reference(frame.config, window, DepthFormat::Window);
  // Same clusters as the view-z form except where the float conversion crosses a slice boundary.
  const auto layout = ClusterLayout::make(frame.config);
  const auto from_view = reference_keys(layout, frame.depth.view_z, DepthFormat::ViewZ);
  const auto from_window = reference_keys(layout, window, DepthFormat::Window);
  std::size_t differ = 0;
  for (std::size_t p = 0; p < from_view.size(); ++p) differ += from_view[p] != from_window[p];
  EXPECT_LT(differ, from_view.size() / 100);
}

// Random depth per pixel: every tile spans all slices, with random normals the (slice, normal)
// range per tile exceeds the counting-sort bins, so the per-tile radix sort runs too. Includes
// background and out-of-range samples.
TEST(ClusterKeys, NoiseDepthWithNormalsExercisesEveryPath) {
  ClusterConfig config;
  config.width = 96;
  config.height = 80;
  config.tile_width = 32;
  config.tile_height = 16;
  config.near_plane = 0.25f;
  config.far_plane = 300.0f;
  config.normal_bits = true;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> log_distance(std::log(0.2f), std::log(400.0f));
  std::normal_distribution<float> gauss;
  std::vector<float> depth(std::size_t{config.width} * config.height);
  std::vector<Vec3> normals(depth.size());
  for (std::size_t p = 0; p < depth.size(); ++p) {
    depth[p] = p % 17 == 0 ? kBackgroundViewZ : -std::exp(log_distance(random));
    normals[p] = normalized(Vec3{gauss(random), gauss(random), gauss(random)});
  }
  depth[1] = -config.near_plane;
  depth[2] = -config.far_plane;
  expect_all_variants_match_reference(config, depth, DepthFormat::ViewZ, &normals);
}

TEST(ClusterKeys, EmptyFrameHasNoClusters) {
  const auto frame = make_frame(15, 64, 48);
  std::vector<float> depth(frame.depth.view_z.size(), kBackgroundViewZ);
  expect_all_variants_match_reference(frame.config, depth, DepthFormat::ViewZ);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  pipeline.upload_depth(depth, DepthFormat::ViewZ);
  pipeline.compute_keys();
  EXPECT_EQ(pipeline.compact(Compaction::TileSort), 0u);
}

TEST(ClusterKeys, OnePixelFrame) {
  ClusterConfig config;
  config.width = config.height = 1;
  expect_all_variants_match_reference(config, {-3.0f}, DepthFormat::ViewZ);
  expect_all_variants_match_reference(config, {kBackgroundViewZ}, DepthFormat::ViewZ);
}

TEST(ClusterKeys, SingleTileFrame) {
  const auto frame = make_frame(16, 30, 20);
  ASSERT_EQ(ClusterLayout::make(frame.config).tile_count, 1u);
  expect_all_variants_match_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ);
}

TEST(ClusterKeys, AllPixelsOneDepthGiveOneClusterPerTile) {
  auto frame = make_frame(17, 100, 70, 16, 16);
  const std::vector<float> depth(frame.depth.view_z.size(), -5.0f);
  expect_all_variants_match_reference(frame.config, depth, DepthFormat::ViewZ);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  pipeline.upload_depth(depth, DepthFormat::ViewZ);
  pipeline.compute_keys();
  EXPECT_EQ(pipeline.compact(Compaction::TileBitmask), pipeline.layout().tile_count);
}

// The largest tile each shape sorts on this device (64×64 where local memory allows: PoCL, Intel;
// 64×32 on Oclgrind's 32 KiB) matches the reference; the next larger tile is a clear error.
TEST(ClusterKeys, LargestSortableTile) {
  const DeviceInfo& device = test_runtime().info();
  for (Shape shape : {Shape::Cpu, Shape::Gpu}) {
    const std::uint32_t pixels = max_sort_tile_pixels(device, shape);
    SCOPED_TRACE(std::string("shape ") + to_string(shape) + ", largest sortable tile " + std::to_string(pixels));
    ASSERT_GE(pixels, 256u) << "a device with " << device.local_mem_bytes << " B local memory sorts 16x16 tiles";
    if (shape == Shape::Gpu) {
      EXPECT_LE(tile_sort_local_bytes(device, pixels), device.local_mem_bytes);
    }
    const std::uint32_t tile_w = std::min<std::uint32_t>(64, pixels), tile_h = pixels / tile_w;
    const auto frame = make_frame(18, 150, 100, tile_w, tile_h);
    expect_all_variants_match_reference(frame.config, frame.depth.view_z, DepthFormat::ViewZ, nullptr, {shape});
    if (pixels < kMaxSortTilePixels) {
      const auto larger = make_frame(18, 150, 100, tile_w, tile_h * 2);
      ClusterPipeline pipeline(test_runtime(), larger.config, shape);
      pipeline.upload_depth(larger.depth.view_z, DepthFormat::ViewZ);
      pipeline.compute_keys();
      EXPECT_THROW(pipeline.compact(Compaction::TileSort), Error);
    }
  }
  EXPECT_EQ(max_sort_tile_pixels(device, Shape::Cpu), kMaxSortTilePixels);
  DeviceInfo gpu_32k = device;  // the limits of Oclgrind and of GPUs with 32 or 48 KiB
  gpu_32k.local_mem_bytes = 32 * 1024;
  gpu_32k.max_work_group_size = 256;
  EXPECT_EQ(max_sort_tile_pixels(gpu_32k, Shape::Gpu), 2048u);
  DeviceInfo gpu_48k = gpu_32k;
  gpu_48k.local_mem_bytes = 48 * 1024;
  EXPECT_EQ(max_sort_tile_pixels(gpu_48k, Shape::Gpu), 4096u);
  EXPECT_EQ(tile_sort_local_bytes(gpu_48k, 4096), 33792u);
  DeviceInfo small_groups = gpu_48k;  // 64 work-items per group: 64×64 tiles sort 64 pairs per item
  small_groups.max_work_group_size = 64;
  EXPECT_EQ(tile_sort_group(small_groups, 4096), 64u);
}

TEST(ClusterKeys, VariantLimitsAreClearErrors) {
  auto frame = make_frame(19, 200, 200, 128, 64);  // tile of 8192 pixels: too large to sort per tile
  ClusterPipeline pipeline(test_runtime(), frame.config);
  pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  pipeline.compute_keys();
  EXPECT_THROW(pipeline.compact(Compaction::TileSort), Error);
  const auto reference = reference_compact(reference_keys(pipeline.layout(), frame.depth.view_z, DepthFormat::ViewZ));
  pipeline.compact(Compaction::TileBitmask);
  EXPECT_EQ(pipeline.download_clusters(), reference);

  ClusterConfig thin = frame.config;  // 1-pixel tile rows: many slices; with normal bits > 16 bits
  thin.tile_width = 8;
  thin.tile_height = 1;
  thin.normal_bits = true;
  ClusterPipeline thin_pipeline(test_runtime(), thin);
  ASSERT_GT(thin_pipeline.layout().low_bits(), kMaxBitmaskLowBits);
  thin_pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  thin_pipeline.upload_normals(frame.depth.normals);
  thin_pipeline.compute_keys();
  EXPECT_THROW(thin_pipeline.compact(Compaction::TileBitmask), Error);
}

TEST(ClusterKeys, InputsAndStageOrderAreChecked) {
  const auto frame = make_frame(20, 64, 48, 32, 32, true);
  ClusterPipeline pipeline(test_runtime(), frame.config);
  EXPECT_THROW(pipeline.compute_keys(), Error);
  EXPECT_THROW(pipeline.upload_depth(std::vector<float>(10), DepthFormat::ViewZ), Error);
  pipeline.upload_depth(frame.depth.view_z, DepthFormat::ViewZ);
  EXPECT_THROW(pipeline.compute_keys(), Error);  // normal bits without normals
  EXPECT_THROW(pipeline.upload_normals(std::vector<Vec3>(3)), Error);
  pipeline.upload_normals(frame.depth.normals);
  EXPECT_THROW(pipeline.compact(Compaction::TileSort), Error);
  pipeline.compute_keys();
  EXPECT_THROW(pipeline.compute_bounds(), Error);
  EXPECT_THROW(parse_compaction("quick"), Error);
  EXPECT_EQ(parse_compaction("tile-sort"), Compaction::TileSort);
}

}  // namespace
}  // namespace splatcl::cluster
