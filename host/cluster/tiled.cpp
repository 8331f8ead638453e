#include "cluster/tiled.hpp"

#include <algorithm>
#include <cmath>

namespace splatcl::cluster {

TiledLights tiled_light_lists(const ClusterLayout& layout, const std::vector<float>& view_z,
                              const std::vector<PointLight>& lights) {
  const std::uint32_t width = layout.config.width, height = layout.config.height;
  const std::uint32_t tile_w = layout.config.tile_width, tile_h = layout.config.tile_height;
  TiledLights out;
  out.pixel_list.assign(view_z.size(), kNoCluster);
  const std::uint32_t tiles = layout.tile_count;
  std::vector<float> near_d(tiles, INFINITY), far_d(tiles, 0.0f);
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) {
      const std::size_t p = std::size_t{y} * width + x;
      const auto d = pixel_distance(layout, view_z[p], DepthFormat::ViewZ);
      if (!d) continue;
      const std::uint32_t t = layout.tile_of_pixel(x, y);
      near_d[t] = std::min(near_d[t], *d);
      far_d[t] = std::max(far_d[t], *d);
      out.pixel_list[p] = t;
    }
  LightLists& lists = out.lists;
  lists.offsets.assign(tiles, 0);
  lists.counts.assign(tiles, 0);
  for (std::uint32_t t = 0; t < tiles; ++t) {
    lists.offsets[t] = static_cast<std::uint32_t>(lists.indices.size());
    if (!(near_d[t] <= far_d[t])) continue;
    const std::uint32_t tx = t % layout.tiles_x, ty = t / layout.tiles_x;
    const float x0 = static_cast<float>(tx * tile_w) * layout.two_over_width - 1.0f;
    const float x1 = std::min(static_cast<float>((tx + 1) * tile_w) * layout.two_over_width - 1.0f, 1.0f);
    const float y0 = static_cast<float>(ty * tile_h) * layout.two_over_height - 1.0f;
    const float y1 = std::min(static_cast<float>((ty + 1) * tile_h) * layout.two_over_height - 1.0f, 1.0f);
    ClusterBox box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (const float d : {near_d[t], far_d[t]})
      for (const float nx : {x0, x1})
        for (const float ny : {y0, y1}) {
          const Vec3 v{nx * d * layout.tan_half_x, ny * d * layout.tan_half_y, -d};
          box.min = {std::min(box.min.x, v.x), std::min(box.min.y, v.y), std::min(box.min.z, v.z)};
          box.max = {std::max(box.max.x, v.x), std::max(box.max.y, v.y), std::max(box.max.z, v.z)};
        }
    const float pad = 1e-4f * far_d[t];  // float rounding of reconstructed positions
    box.min = box.min - Vec3{pad, pad, pad};
    box.max = box.max + Vec3{pad, pad, pad};
    for (std::uint32_t i = 0; i < lights.size(); ++i)
      if (light_touches_box(lights[i], box)) lists.indices.push_back(i);
    lists.counts[t] = static_cast<std::uint32_t>(lists.indices.size()) - lists.offsets[t];
  }
  return out;
}

}  // namespace splatcl::cluster
