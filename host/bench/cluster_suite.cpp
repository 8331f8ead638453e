// splatcl bench cluster: the clustered-shading stages of one 1920×1080 frame, stage by stage, in both
// kernel shapes against the native reference, with the sort + unique peers and the bandwidth limit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bench/bandwidth.hpp"
#include "bench/peer_cases.hpp"
#include "bench/suites.hpp"
#include "cluster/cluster.hpp"
#include "cluster/reference.hpp"
#include "cluster/scene_input.hpp"
#include "core/scene.hpp"
#include "core/scene_ray_cast.hpp"

namespace splatcl::bench {
namespace {

namespace clu = splatcl::cluster;

constexpr std::uint32_t kWidth = 1920;
constexpr std::uint32_t kHeight = 1080;
constexpr std::uint32_t kTileSize = 32;
constexpr std::uint32_t kLightCounts[] = {1024, 16384, 262144};
// Light radii at 1k lights. Radii shrink with the cube root of the
// count, so every count fills the scene with about the same light density per cluster, as a
// many-light scene does; otherwise 256k lights would each reach thousands of clusters.
constexpr std::uint32_t kBaseLightCount = 1024;
constexpr float kLightRadiusMin = 0.5f;
constexpr float kLightRadiusMax = 2.0f;
constexpr clu::Compaction kCompactions[] = {clu::Compaction::GlobalSort, clu::Compaction::TileSort,
                                            clu::Compaction::TileBitmask};
constexpr clu::Assignment kAssignments[] = {clu::Assignment::BruteForce, clu::Assignment::Hierarchy};

// One pipeline per kernel shape, kept across stages: each stage consumes the previous one's buffers.
struct ShapedPipeline {
  Shape shape;
  std::unique_ptr<clu::ClusterPipeline> pipeline;
};

// A ray-cast frame of the default scene (data/presenter-scene.json), with the window depth a GL
// depth buffer holds.
struct Frame {
  Scene scene;
  DepthFrame depth;
  std::vector<float> window_depth;
  clu::ClusterConfig config;
};

// --quick: a 320×180 frame with 1k lights, for smoke tests.
constexpr std::uint32_t kQuickWidth = 320;
constexpr std::uint32_t kQuickHeight = 180;

Frame make_frame(std::uint32_t width, std::uint32_t height) {
  Frame frame;
  frame.scene = default_scene();
  frame.depth = ray_cast(frame.scene, width, height);
  frame.window_depth = clu::window_depth(frame.depth, frame.scene.camera);
  frame.config = clu::cluster_config(frame.scene.camera, width, height, kTileSize, kTileSize);
  return frame;
}

std::pair<float, float> light_radius_range(std::uint32_t count) {
  const float scale = std::cbrt(static_cast<float>(kBaseLightCount) / static_cast<float>(count));
  return {kLightRadiusMin * scale, kLightRadiusMax * scale};
}

std::vector<clu::PointLight> make_lights(Frame& frame, std::uint32_t count) {
  const auto [radius_min, radius_max] = light_radius_range(count);
  // The scene's generator, over its floor at its heights, with a seed per count.
  frame.scene.generated.radius_min = radius_min;
  frame.scene.generated.radius_max = radius_max;
  frame.scene.generated.seed = count;
  set_generated_light_count(frame.scene, count);
  return clu::view_lights(frame.scene.lights, view_frame(frame.scene.camera));
}

// Times stage(pipeline, profiler) on every pipeline as an OpenCL row of case `name`, then calls
// check(pipeline, description) on its output.
template <class Stage, class Check>
void measure_pipelines(Session& session, std::vector<ShapedPipeline>& pipelines, const std::string& name,
                       std::uint64_t size, const std::string& unit, const Json& problem, const Json& implementation,
                       Stage&& stage, Check&& check) {
  for (auto& [shape, pipeline] : pipelines) {
    Profiler profiler;
    const Case c = opencl_case(name, shape, size, unit, problem, implementation);
    session.measure(c, {}, [&] {
      stage(*pipeline, &profiler);
      pipeline->finish();
    }, &profiler);
    check(*pipeline, describe(c));
  }
}

// The frame's side scaled by √scale (at least one pixel), so its pixel count follows the scale.
std::uint32_t scaled_side(const Session& session, std::uint32_t side) {
  const double value = std::round(static_cast<double>(side) * std::sqrt(session.options().scale));
  return value < 1 ? 1u : static_cast<std::uint32_t>(value);
}

}  // namespace

void run_cluster_suite(Session& session) {
  const bool quick = session.options().quick;
  Frame frame = make_frame(scaled_side(session, quick ? kQuickWidth : kWidth), scaled_side(session, quick ? kQuickHeight : kHeight));
  const clu::ClusterLayout layout = clu::ClusterLayout::make(frame.config);
  const std::uint64_t pixels = layout.pixel_count();

  std::vector<ShapedPipeline> pipelines;
  for (const Shape shape : kBothShapes) {
    pipelines.push_back({shape, std::make_unique<clu::ClusterPipeline>(session.runtime(), frame.config, shape)});
    pipelines.back().pipeline->upload_depth(frame.window_depth, clu::DepthFormat::Window);
  }

  // Keys.
  std::vector<std::uint32_t> keys;
  const auto compute_reference_keys = [&] { keys = clu::reference_keys(layout, frame.window_depth, clu::DepthFormat::Window); };
  compute_reference_keys();
  measure_pipelines(session, pipelines, "keys", pixels, "pixels", {}, {},
                    [](clu::ClusterPipeline& p, Profiler* profiler) { p.compute_keys(profiler); },
                    [&](clu::ClusterPipeline& p, const std::string& what) { expect_same_output(what, p.download_keys(), keys); });
  session.measure(reference_case("keys", pixels, "pixels"), {}, compute_reference_keys);

  // Compaction: every variant, the reference, and the sort + unique peers on the same keys.
  const clu::ClusterList clusters = clu::reference_compact(keys);
  for (const clu::Compaction compaction : kCompactions) {
    measure_pipelines(
        session, pipelines, "compact", pixels, "keys", {}, Json{{"variant", clu::to_string(compaction)}},
        [&](clu::ClusterPipeline& p, Profiler* profiler) { p.compact(compaction, profiler); },
        [&](clu::ClusterPipeline& p, const std::string& what) {
          const clu::ClusterList result = p.download_clusters();
          expect_same_output(what + " unique keys", result.unique_keys, clusters.unique_keys);
          expect_same_output(what + " pixel clusters", result.pixel_cluster, clusters.pixel_cluster);
        });
  }
  clu::ClusterList reference_clusters;
  session.measure(reference_case("compact", pixels, "keys"), {}, [&] { reference_clusters = clu::reference_compact(keys); });
  std::vector<std::uint32_t> sorted_unique = keys;
  std::sort(sorted_unique.begin(), sorted_unique.end());
  sorted_unique.erase(std::unique(sorted_unique.begin(), sorted_unique.end()), sorted_unique.end());
  measure_sort_peers(session, Case{"compact", "", false, pixels, "keys"}, PeerWork::SortUnique, keys, sorted_unique);

  // Cluster bounds.
  const std::uint64_t cluster_count = clusters.unique_keys.size();
  const std::vector<clu::ClusterBox> bounds = clu::reference_bounds(layout, clusters.unique_keys);
  measure_pipelines(session, pipelines, "bounds", cluster_count, "clusters", {}, {},
                    [](clu::ClusterPipeline& p, Profiler* profiler) { p.compute_bounds(profiler); },
                    [&](clu::ClusterPipeline& p, const std::string& what) { expect_same_output(what, p.download_bounds(), bounds); });
  std::vector<clu::ClusterBox> reference_boxes;
  session.measure(reference_case("bounds", cluster_count, "clusters"), {},
                  [&] { reference_boxes = clu::reference_bounds(layout, clusters.unique_keys); });

  // Light assignment, per light count. The device lists are checked against the reference's after
  // it has been timed, since at 256k lights one reference run is itself expensive.
  for (const std::uint32_t light_count : kLightCounts) {
    if (quick && light_count != kLightCounts[0]) continue;
    const std::vector<clu::PointLight> lights = make_lights(frame, light_count);
    for (auto& entry : pipelines) entry.pipeline->upload_lights(lights);
    const auto [radius_min, radius_max] = light_radius_range(light_count);
    const Json problem{{"lights", light_count}, {"light_radius", {radius_min, radius_max}}};
    std::vector<std::pair<std::string, clu::LightLists>> device_lists;
    for (const clu::Assignment assignment : kAssignments) {
      Json implementation{{"variant", clu::to_string(assignment)}};
      // Brute force, counted from kernels/cluster_lights.cl: per cluster and light (padded to 8),
      // 19 float operations in the sphere-box test (6 subtractions, 6 max, 4 multiplies, 2 adds, a
      // compare), once to count and once to fill.
      if (assignment == clu::Assignment::BruteForce) implementation["flops"] = 2 * 19 * cluster_count * ((light_count + 7) / 8 * 8);
      measure_pipelines(
          session, pipelines, "assign-lights", cluster_count, "clusters", problem, implementation,
          [&](clu::ClusterPipeline& p, Profiler* profiler) { p.assign_lights(assignment, profiler); },
          [&](clu::ClusterPipeline& p, const std::string& what) { device_lists.emplace_back(what, p.download_light_lists()); });
    }
    clu::LightLists expected;
    session.measure(reference_case("assign-lights", cluster_count, "clusters", problem), {},
                    [&] { expected = clu::reference_assign(bounds, lights); });
    for (const auto& [what, lists] : device_lists) {
      expect_same_output(what + " light offsets", lists.offsets, expected.offsets);
      expect_same_output(what + " light counts", lists.counts, expected.counts);
      expect_same_output(what + " light indices", lists.indices, expected.indices);
    }
  }

  measure_ceilings(session, quick ? kQuickStreamArrayBytes : kStreamArrayBytes);
}

}  // namespace splatcl::bench
