// Tiled light lists (cluster/tiled.hpp), the presenter's tiled baseline: conservative against the
// lights that reach each covered pixel, empty where nothing is covered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cluster/tiled.hpp"

namespace splatcl::cluster {
namespace {

ClusterLayout small_layout() {
  ClusterConfig c;
  c.width = 70;  // not a multiple of the tile: the last column of tiles is narrower
  c.height = 50;
  c.tile_width = c.tile_height = 16;
  c.fov_y = 1.0f;
  c.near_plane = 0.1f;
  c.far_plane = 100.0f;
  return ClusterLayout::make(c);
}

TEST(TiledLightLists, EveryLightReachingACoveredPixelIsInItsTileList) {
  const ClusterLayout layout = small_layout();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> view_z(layout.pixel_count(), 0.0f);
  for (float& z : view_z)
    if (unit(rng) < 0.7f) z = -(1.0f + 9.0f * unit(rng));  // 30 % background
  std::vector<PointLight> lights;
  for (int i = 0; i < 200; ++i)
    lights.push_back({{12.0f * unit(rng) - 6.0f, 8.0f * unit(rng) - 4.0f, -12.0f * unit(rng)}, 0.2f + 1.5f * unit(rng), {1, 1, 1}});
  const TiledLights tiled = tiled_light_lists(layout, view_z, lights);
  ASSERT_EQ(tiled.pixel_list.size(), view_z.size());
  ASSERT_EQ(tiled.lists.offsets.size(), layout.tile_count);
  std::size_t reached = 0;
  for (std::uint32_t y = 0; y < layout.config.height; ++y)
    for (std::uint32_t x = 0; x < layout.config.width; ++x) {
      const std::size_t p = std::size_t{y} * layout.config.width + x;
      if (view_z[p] == 0.0f) {
        EXPECT_EQ(tiled.pixel_list[p], kNoCluster);
        continue;
      }
      const std::uint32_t t = tiled.pixel_list[p];
      ASSERT_EQ(t, layout.tile_of_pixel(x, y));
      const auto begin = tiled.lists.indices.begin() + tiled.lists.offsets[t];
      const auto end = begin + tiled.lists.counts[t];
      const Vec3 v = pixel_view_position(layout, x, y, -view_z[p]);
      for (std::uint32_t i = 0; i < lights.size(); ++i) {
        const Vec3 d = lights[i].center - v;
        if (d.x * d.x + d.y * d.y + d.z * d.z >= 0.99f * lights[i].radius * lights[i].radius) continue;
        ++reached;
        EXPECT_NE(std::find(begin, end, i), end) << "light " << i << " pixel " << x << "," << y;
      }
    }
  EXPECT_GT(reached, 100u);  // the check is not vacuous
}

TEST(TiledLightLists, UncoveredTilesHaveEmptyLists) {
  const ClusterLayout layout = small_layout();
  std::vector<float> view_z(layout.pixel_count(), 0.0f);
  view_z[0] = -2.0f;  // one covered pixel, in tile 0
  const std::vector<PointLight> lights = {{{0, 0, -2}, 50.0f, {1, 1, 1}}};  // reaches everything in range
  const TiledLights tiled = tiled_light_lists(layout, view_z, lights);
  EXPECT_EQ(tiled.pixel_list[0], 0u);
  EXPECT_EQ(tiled.lists.counts[0], 1u);
  for (std::uint32_t t = 1; t < layout.tile_count; ++t) EXPECT_EQ(tiled.lists.counts[t], 0u) << "tile " << t;
  EXPECT_EQ(tiled.lists.indices.size(), 1u);
}

}  // namespace
}  // namespace splatcl::cluster
