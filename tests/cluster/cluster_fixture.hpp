#pragma once
// Shared by the cluster tests: one runtime per process, ray-cast frames of random scenes, and the
// invariant checks every variant must pass.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include "runtime/test_runtime.hpp"
#include "cluster/cluster.hpp"
#include "cluster/reference.hpp"
#include "cluster/scene_input.hpp"
#include "core/scene.hpp"
#include "core/scene_ray_cast.hpp"

namespace splatcl::cluster::testing {

inline Runtime& test_runtime() { return splatcl::testing::shared_runtime(); }

// SplitMix64: the same sequence on every platform (unlike std distributions).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  // Uniform in [lo, hi).
  float uniform(float lo, float hi) {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<float>(z >> 40) * 0x1.0p-24f;
  }

 private:
  std::uint64_t state_;
};

// A scene of `spheres` spheres and `boxes` boxes standing on a floor within [−extent, extent] in
// x and z, a camera looking at it from a seed-chosen direction, and `light_count` generated lights
// over the floor up to 0.4·extent high. Deterministic per seed.
inline Scene random_scene(std::uint64_t seed, std::uint32_t light_count = 200, std::uint32_t spheres = 12,
                          std::uint32_t boxes = 8, float extent = 10.0f) {
  Random random(seed);
  const float e = extent;
  Scene scene;
  scene.source = "random scene " + std::to_string(seed);
  scene.floor.size = 2.4f * e;
  for (std::uint32_t i = 0; i < spheres; ++i) {
    ObjectSpec sphere;
    sphere.mesh.procedural = "sphere";
    sphere.mesh.radius = random.uniform(0.03f, 0.15f) * e;
    sphere.mesh.segments = 24;
    sphere.mesh.rings = 12;
    sphere.position = {random.uniform(-e, e), sphere.mesh.radius + random.uniform(0, 0.2f) * e, random.uniform(-e, e)};
    scene.objects.push_back(sphere);
  }
  for (std::uint32_t i = 0; i < boxes; ++i) {
    ObjectSpec box;
    box.mesh.procedural = "box";
    box.mesh.size = {random.uniform(0.05f, 0.3f) * e, random.uniform(0.05f, 0.4f) * e, random.uniform(0.05f, 0.3f) * e};
    box.mesh.rings = 1;
    box.position = {random.uniform(-e, e), 0.5f * box.mesh.size.y, random.uniform(-e, e)};
    scene.objects.push_back(box);
  }
  const float angle = random.uniform(0.0f, 6.2831853f);
  const float distance = random.uniform(1.2f, 1.8f) * e;
  scene.camera.eye = {distance * std::cos(angle), random.uniform(0.2f, 0.6f) * e, distance * std::sin(angle)};
  scene.camera.target = {0, 0, 0};
  scene.camera.near_plane = 0.1f;
  scene.camera.far_plane = 10.0f * e;
  scene.generated = {0, 0.3f, 2.5f, 0.0f, 0.4f * e, e, 0.6f, seed + 1000};
  set_generated_light_count(scene, light_count);
  return scene;
}

// A ray-cast random scene with its lights, ready for the pipeline.
struct Frame {
  Scene scene;
  DepthFrame depth;
  ClusterConfig config;
  std::vector<PointLight> lights;
};

inline Frame make_frame(std::uint64_t seed, std::uint32_t width, std::uint32_t height, std::uint32_t tile_width = 32,
                        std::uint32_t tile_height = 32, bool normal_bits = false, std::uint32_t light_count = 200) {
  Frame frame;
  frame.scene = random_scene(seed, light_count);
  frame.depth = ray_cast(frame.scene, width, height);
  frame.config = cluster_config(frame.scene.camera, width, height, tile_width, tile_height, normal_bits);
  frame.lights = view_lights(frame.scene.lights, view_frame(frame.scene.camera));
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
