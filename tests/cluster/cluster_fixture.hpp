#pragma once
// Shared by the cluster tests: one runtime per process, frames from the test-scene generator,
// and the invariant checks every variant must pass.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include "runtime/test_runtime.hpp"
#include "cluster/cluster.hpp"
#include "cluster/reference.hpp"
#include "cluster/test_scene.hpp"

namespace splatcl::cluster::testing {

inline Runtime& test_runtime() { return splatcl::testing::shared_runtime(); }

// A ray-cast random scene with its lights, ready for the pipeline.
struct Frame {
  Scene scene;
  DepthFrame depth;
  ClusterConfig config;
  std::vector<PointLight> lights;
};

inline Frame make_frame(std::uint64_t seed, std::uint32_t width, std::uint32_t height, std::uint32_t tile_width = 32,
                        std::uint32_t tile_height = 32, bool normal_bits = false, std::uint32_t light_count = 200) {
  RandomSceneOptions options;
  options.lights = {light_count, 0.3f, 2.5f, seed + 1000};
  Frame frame;
  frame.scene = random_scene(seed, options);
  frame.depth = ray_cast(frame.scene, width, height);
  frame.config = cluster_config(frame.scene.camera, width, height, tile_width, tile_height, normal_bits);
  frame.lights = view_lights(frame.scene, frame.depth);
  return frame;
}

struct Results {
  std::vector<std::uint32_t> keys;
  ClusterList clusters;
  std::vector<ClusterBox> bounds;
  LightLists lights;
};

// Runs every stage on `pipeline` (inputs already uploaded) and downloads everything.
inline Results run_stages(ClusterPipeline& pipeline, Compaction compaction, Assignment assignment) {
  Results r;
  pipeline.compute_keys();
  r.keys = pipeline.download_keys();
  const std::uint32_t count = pipeline.compact(compaction);
  r.clusters = pipeline.download_clusters();
  EXPECT_EQ(count, r.clusters.unique_keys.size());
  pipeline.compute_bounds();
  r.bounds = pipeline.download_bounds();
  pipeline.assign_lights(assignment);
  r.lights = pipeline.download_light_lists();
  return r;
}

// uniqueKey strictly increasing, uniqueKey[pixelCluster[p]] == key[p], background ↔ kNoCluster,
// and the count equals the number of distinct valid keys.
inline void expect_compaction_invariants(const std::vector<std::uint32_t>& keys, const ClusterList& clusters) {
  const auto& unique = clusters.unique_keys;
  for (std::size_t c = 1; c < unique.size(); ++c) ASSERT_LT(unique[c - 1], unique[c]) << "at " << c;
  ASSERT_EQ(clusters.pixel_cluster.size(), keys.size());
  std::set<std::uint32_t> distinct;
  for (std::size_t p = 0; p < keys.size(); ++p) {
    if (keys[p] == kBackgroundKey) {
      ASSERT_EQ(clusters.pixel_cluster[p], kNoCluster) << "pixel " << p;
      continue;
    }
    distinct.insert(keys[p]);
    ASSERT_LT(clusters.pixel_cluster[p], unique.size()) << "pixel " << p;
    ASSERT_EQ(unique[clusters.pixel_cluster[p]], keys[p]) << "pixel " << p;
  }
  EXPECT_EQ(unique.size(), distinct.size());
}

// Every listed light touches its cluster's box, and lists are ascending without repeats.
inline void expect_listed_lights_touch(const std::vector<ClusterBox>& boxes, const std::vector<PointLight>& lights,
                                       const LightLists& lists) {
  ASSERT_EQ(lists.offsets.size(), boxes.size());
  ASSERT_EQ(lists.counts.size(), boxes.size());
  std::size_t expected_offset = 0;
  for (std::size_t c = 0; c < boxes.size(); ++c) {
    ASSERT_EQ(lists.offsets[c], expected_offset) << "cluster " << c;
    expected_offset += lists.counts[c];
    ASSERT_LE(expected_offset, lists.indices.size());
    for (std::uint32_t n = 0; n < lists.counts[c]; ++n) {
      const std::uint32_t light = lists.indices[lists.offsets[c] + n];
      ASSERT_LT(light, lights.size());
      if (n > 0) {
        ASSERT_LT(lists.indices[lists.offsets[c] + n - 1], light) << "cluster " << c;
      }
      ASSERT_TRUE(light_touches_box(lights[light], boxes[c])) << "cluster " << c << " light " << light;
    }
  }
  EXPECT_EQ(expected_offset, lists.indices.size());
}

// No false negatives: every light whose sphere contains a pixel's view-space position is in the
// list of that pixel's cluster (positions in double, independent of the kernels' float math).
inline void expect_no_false_negatives(const ClusterLayout& layout, const std::vector<float>& depth, DepthFormat format,
                                      const ClusterList& clusters, const LightLists& lists,
                                      const std::vector<PointLight>& lights) {
  const std::uint32_t width = layout.config.width;
  std::size_t checked = 0;
  for (std::size_t p = 0; p < depth.size(); ++p) {
    const auto distance = pixel_distance(layout, depth[p], format);
    const std::uint32_t c = clusters.pixel_cluster[p];
    if (!distance) {
      ASSERT_EQ(c, kNoCluster);
      continue;
    }
    const auto x = static_cast<std::uint32_t>(p % width), y = static_cast<std::uint32_t>(p / width);
    const double d = *distance;
    const double px = ((x + 0.5) * 2.0 / layout.config.width - 1.0) * d * layout.tan_half_x;
    const double py = ((y + 0.5) * 2.0 / layout.config.height - 1.0) * d * layout.tan_half_y;
    const double pz = -d;
    const auto first = lists.indices.begin() + lists.offsets[c];
    const auto last = first + lists.counts[c];
    for (std::uint32_t l = 0; l < lights.size(); ++l) {
      const double dx = px - lights[l].center.x, dy = py - lights[l].center.y, dz = pz - lights[l].center.z;
      const double r = lights[l].radius;
      if (dx * dx + dy * dy + dz * dz > r * r) continue;
      ++checked;
      ASSERT_TRUE(std::binary_search(first, last, l)) << "pixel " << p << " light " << l << " cluster " << c;
    }
  }
  ::testing::Test::RecordProperty("lit_pixel_light_pairs", static_cast<int>(checked));
}

}  // namespace splatcl::cluster::testing
