#include "cluster/reference.hpp"

#include <algorithm>

#include "core/parallel.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {

std::vector<std::uint32_t> reference_keys(const ClusterLayout& layout, const std::vector<float>& depth,
                                          DepthFormat format, const std::vector<Vec3>* normals) {
  if (depth.size() != layout.pixel_count()) throw Error("reference_keys: depth buffer size does not match the frame");
  const bool use_normals = layout.normal_bits > 0;
  if (use_normals && (!normals || normals->size() != layout.pixel_count()))
    throw Error("reference_keys: normal-bit keys need one normal per pixel");
  std::vector<std::uint32_t> keys(depth.size(), kBackgroundKey);
  const std::uint32_t width = layout.config.width;
  for (std::uint32_t y = 0; y < layout.config.height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      const std::size_t p = std::size_t{y} * width + x;
      const auto distance = pixel_distance(layout, depth[p], format);
      if (!distance) continue;
      keys[p] = layout.pack(layout.tile_of_pixel(x, y), slice_of_distance(layout, *distance),
                            use_normals ? normal_cell((*normals)[p]) : 0u);
    }
  }
  return keys;
}

ClusterList reference_compact(const std::vector<std::uint32_t>& keys) {
  ClusterList list;
  list.unique_keys = keys;
  std::sort(list.unique_keys.begin(), list.unique_keys.end());
  list.unique_keys.erase(std::unique(list.unique_keys.begin(), list.unique_keys.end()), list.unique_keys.end());
  if (!list.unique_keys.empty() && list.unique_keys.back() == kBackgroundKey) list.unique_keys.pop_back();
  list.pixel_cluster.resize(keys.size());
  for (std::size_t p = 0; p < keys.size(); ++p) {
    list.pixel_cluster[p] =
        keys[p] == kBackgroundKey
            ? kNoCluster
            : static_cast<std::uint32_t>(std::lower_bound(list.unique_keys.begin(), list.unique_keys.end(), keys[p]) -
                                         list.unique_keys.begin());
  }
  return list;
}

std::vector<ClusterBox> reference_bounds(const ClusterLayout& layout, const std::vector<std::uint32_t>& unique_keys) {
  std::vector<ClusterBox> boxes;
  boxes.reserve(unique_keys.size());
  for (const auto key : unique_keys) boxes.push_back(cluster_box(layout, key));
  return boxes;
}

LightLists reference_assign(const std::vector<ClusterBox>& boxes, const std::vector<PointLight>& lights) {
  const std::size_t clusters = boxes.size();
  std::vector<std::vector<std::uint32_t>> per_cluster(clusters);
  parallel_for(clusters, 64, [&](std::size_t c, std::size_t) {
    for (std::uint32_t l = 0; l < lights.size(); ++l)
      if (light_touches_box(lights[l], boxes[c])) per_cluster[c].push_back(l);
  });

  LightLists lists;
  lists.offsets.resize(clusters);
  lists.counts.resize(clusters);
  for (std::size_t c = 0; c < clusters; ++c) {
    lists.offsets[c] = static_cast<std::uint32_t>(lists.indices.size());
    lists.counts[c] = static_cast<std::uint32_t>(per_cluster[c].size());
    lists.indices.insert(lists.indices.end(), per_cluster[c].begin(), per_cluster[c].end());
  }
  return lists;
}

}  // namespace splatcl::cluster
