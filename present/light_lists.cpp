#include "present/light_lists.hpp"

#include "cluster/tiled.hpp"
#include "runtime/profiling.hpp"

namespace splatcl::present {

ClusteredLightLists::ClusteredLightLists(Runtime& runtime, const cluster::ClusterConfig& config)
    : pipeline_(runtime, config) {}

FrameLightLists ClusteredLightLists::build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                                           std::vector<StageTime>& stages) {
  FrameLightLists out;
  cluster::ClusterPipeline& p = pipeline_;
  const auto timed = [&](const char* name, auto&& body) {
    Stopwatch c;
    body();
    p.finish();
    stages.push_back({name, c.elapsed_ms()});
  };
  timed("cl: upload depth+lights", [&] {
    p.upload_depth(view_z, cluster::DepthFormat::ViewZ);
    p.upload_lights(lights);
  });
  timed("cl: cluster keys", [&] { p.compute_keys(); });
  timed("cl: compaction", [&] { out.clusters = p.compact(cluster::Compaction::TileBitmask); });
  timed("cl: cluster bounds", [&] { p.compute_bounds(); });
  timed("cl: light assignment", [&] {
    out.light_indices =
        p.assign_lights(lights.size() >= 4096 ? cluster::Assignment::Hierarchy : cluster::Assignment::BruteForce);
  });
  timed("cl: download lists", [&] {
    out.pixel_list = p.download_clusters().pixel_cluster;
    out.lists = p.download_light_lists();
  });
  return out;
}

FrameLightLists TiledLightLists::build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>& lights,
                                       std::vector<StageTime>& stages) {
  Stopwatch c;
  cluster::TiledLights tiled = cluster::tiled_light_lists(layout_, view_z, lights);
  FrameLightLists out;
  out.pixel_list = std::move(tiled.pixel_list);
  out.lists = std::move(tiled.lists);
  out.clusters = layout_.tile_count;
  out.light_indices = static_cast<std::uint32_t>(out.lists.indices.size());
  stages.push_back({"host: tile light lists", c.elapsed_ms()});
  return out;
}

FrameLightLists BruteForceLights::build(const std::vector<float>& view_z, const std::vector<cluster::PointLight>&,
                                        std::vector<StageTime>&) {
  FrameLightLists out;
  out.pixel_list.assign(view_z.size(), cluster::kNoCluster);
  return out;
}

}  // namespace splatcl::present
