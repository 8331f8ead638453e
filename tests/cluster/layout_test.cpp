// Cluster grid, key packing and per-pixel arithmetic (host only).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "cluster/layout.hpp"
#include "cluster/scene_input.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

constexpr float kDegree = 3.14159265358979f / 180.0f;

ClusterConfig config_of(std::uint32_t w, std::uint32_t h, float fov_degrees, float near_plane, float far_plane) {
  ClusterConfig c;
  c.width = w;
  c.height = h;
  c.fov_y = fov_degrees * kDegree;
  c.near_plane = near_plane;
  c.far_plane = far_plane;
  return c;
}

// Cluster keys of Tegelaers §3.3 worked out by hand for 32×32 tiles (the thesis gives no examples).
TEST(ClusterLayout, ReproducesHandWorkedExamples) {
  struct Row {
    std::uint32_t w, h;
    float fov, near_plane, far_plane;
    std::uint32_t tiles_x, tiles_y, slices;
    double q;
  };
  for (const Row& row : {Row{1920, 1080, 60, 0.1f, 1000, 60, 34, 276, 1.03396},
                         Row{1920, 1080, 60, 0.5f, 100, 60, 34, 159, 1.03396},
                         Row{1280, 720, 60, 0.1f, 100, 40, 23, 142, 1.05020},
                         Row{1024, 768, 90, 0.1f, 100, 32, 24, 87, 1.08333}}) {
    const auto layout = ClusterLayout::make(config_of(row.w, row.h, row.fov, row.near_plane, row.far_plane));
    EXPECT_EQ(layout.tiles_x, row.tiles_x);
    EXPECT_EQ(layout.tiles_y, row.tiles_y);
    EXPECT_EQ(layout.slice_count, row.slices) << row.w << "x" << row.h;
    EXPECT_NEAR(layout.q, row.q, 1e-5);
    EXPECT_GE(layout.slice_boundaries.back(), row.far_plane);
  }
}

TEST(ClusterLayout, TileBitsLeaveTheAllOnesTileIdUnused) {
  for (std::uint32_t tiles_x : {1u, 2u, 3u, 7u, 8u, 31u, 32u, 33u, 60u}) {
    auto c = config_of(tiles_x * 32, 64, 60, 0.1f, 100);
    const auto layout = ClusterLayout::make(c);
    EXPECT_LT(layout.tile_count, 1u << layout.tile_bits);
    EXPECT_LE(layout.tile_count, (1u << layout.tile_bits) - 1u);
    const std::uint32_t low_mask = layout.key_bits == 32 ? 0xFFFFFFFFu : (1u << layout.key_bits) - 1u;
    const std::uint32_t largest =
        layout.pack(layout.tile_count - 1, layout.slice_count - 1, layout.normal_bits ? kNormalCells - 1 : 0);
    EXPECT_LT(largest & low_mask, low_mask);
  }
}

TEST(ClusterLayout, PacksAndUnpacksKeys) {
  auto c = config_of(100, 37, 60, 0.1f, 50);
  c.tile_width = 16;
  c.tile_height = 8;
  c.normal_bits = true;
  const auto layout = ClusterLayout::make(c);
  EXPECT_EQ(layout.tiles_x, 7u);
  EXPECT_EQ(layout.tiles_y, 5u);
  EXPECT_EQ(layout.normal_bits, kNormalKeyBits);
  for (std::uint32_t tile = 0; tile < layout.tile_count; ++tile) {
    const std::uint32_t slice = (tile * 7) % layout.slice_count, cell = tile % kNormalCells;
    const auto fields = layout.unpack(layout.pack(tile, slice, cell));
    EXPECT_EQ(fields.tile_y * layout.tiles_x + fields.tile_x, tile);
    EXPECT_EQ(fields.slice, slice);
    EXPECT_EQ(fields.normal_cell, cell);
  }
  EXPECT_EQ(layout.tile_of_pixel(99, 36), layout.tile_count - 1);
  EXPECT_EQ(layout.tile_of_pixel(16, 8), layout.tiles_x + 1);
}

TEST(ClusterLayout, RejectsBadConfigsWithClearErrors) {
  const auto rejects = [](ClusterConfig c, const char* words) {
    try {
      ClusterLayout::make(c);
      ADD_FAILURE() << "accepted a config expected to fail with: " << words;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const auto good = config_of(64, 64, 60, 0.1f, 100);
  auto c = good;
  c.width = 0;
  rejects(c, "empty");
  c = good;
  c.tile_height = 0;
  rejects(c, "zero side");
  c = good;
  c.tile_width = kMaxTileSide + 1;
  rejects(c, "per side");
  c = good;
  c.near_plane = 0;
  rejects(c, "near plane");
  c = good;
  c.near_plane = -1;
  rejects(c, "near plane");
  c = good;
  c.far_plane = 0.1f;
  rejects(c, "far plane");
  c = good;
  c.fov_y = 0;
  rejects(c, "field of view");
  c = good;
  c.fov_y = 4;
  rejects(c, "field of view");
  c = config_of(8192, 8192, 60, 1e-3f, 1e6f);  // 1x1 tiles: 2^26 tiles and thin slices
  c.tile_width = c.tile_height = 1;
  c.fov_y = 120 * kDegree;
  c.normal_bits = true;
  rejects(c, "32-bit cluster keys");
}

// A telescope's field of view: slices would be thinner than the key kernel's first guess allows,
// so they take the thinnest it does (a fov of 0.01 degree at 160x120 was refused, brute-force and
// tiled shading with it; a helper's audit). Every pixel still lands in its slice.
TEST(ClusterLayout, NarrowViewsTakeTheThinnestSlicesAllowed) {
  ClusterConfig c = config_of(160, 120, 0.01f, 0.1f, 50);
  const ClusterLayout layout = ClusterLayout::make(c);
  EXPECT_NEAR(layout.q, 1.0 + 2e-4, 1e-12);
  EXPECT_GT(layout.slice_count, 1u);
  EXPECT_LE(layout.key_bits, 32u);
}

// The slice of a distance is floor(ln(d/near)/ln q) (Tegelaers §3.3.1 with its logarithm corrected), except
// within rounding distance of a slice boundary, where the boundary table decides.
TEST(ClusterLayout, SliceOfDistanceFollowsTheCorrectedFormula) {
  const auto layout = ClusterLayout::make(config_of(1920, 1080, 60, 0.1f, 1000));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> log_uniform(std::log(0.1), std::log(1000.0));
  for (int i = 0; i < 100000; ++i) {
    const float d = static_cast<float>(std::exp(log_uniform(random)));
    const double exact = std::log(double{d} / 0.1) / std::log(layout.q);
    const std::uint32_t k = slice_of_distance(layout, d);
    ASSERT_LE(layout.slice_boundaries[k], d);
    if (k + 1 < layout.slice_count) {
      ASSERT_LT(d, layout.slice_boundaries[k + 1]);
    }
    if (std::abs(exact - std::round(exact)) > 1e-4) {
      ASSERT_EQ(k, std::min<std::uint32_t>(static_cast<std::uint32_t>(std::floor(exact)), layout.slice_count - 1))
          << d;
    }
  }
  EXPECT_EQ(slice_of_distance(layout, 0.1f), 0u);
  EXPECT_EQ(slice_of_distance(layout, 1000.0f), layout.slice_count - 1);
}

TEST(ClusterLayout, PixelDistanceHonoursBothDepthFormats) {
  const auto layout = ClusterLayout::make(config_of(64, 64, 60, 0.5f, 50));
  EXPECT_EQ(pixel_distance(layout, -2.0f, DepthFormat::ViewZ), 2.0f);
  EXPECT_FALSE(pixel_distance(layout, kBackgroundViewZ, DepthFormat::ViewZ));
  EXPECT_FALSE(pixel_distance(layout, -0.4f, DepthFormat::ViewZ));  // in front of the near plane
  EXPECT_FALSE(pixel_distance(layout, -51.0f, DepthFormat::ViewZ));  // beyond the far plane
  EXPECT_FALSE(pixel_distance(layout, std::nanf(""), DepthFormat::ViewZ));
  EXPECT_EQ(pixel_distance(layout, 1.0f, DepthFormat::Window), 0.5f);  // reversed: 1 at the near plane
  EXPECT_FALSE(pixel_distance(layout, 0.0f, DepthFormat::Window));      // the clear value
  EXPECT_FALSE(pixel_distance(layout, 1.1f, DepthFormat::Window));
  for (float z : {-0.5f, -0.7f, -3.0f, -10.0f, -49.0f}) {
    const float window = window_depth_from_view_z(z, 0.5f, 50.0f);
    EXPECT_GT(window, 0.0f);
    EXPECT_LE(window, 1.0f);
    EXPECT_NEAR(view_z_from_window_depth(window, 0.5f, 50.0f), z, 1e-4f * -z);
    EXPECT_NEAR(*pixel_distance(layout, window, DepthFormat::Window), -z, 1e-4f * -z);
  }
  EXPECT_FLOAT_EQ(view_z_from_window_depth(1.0f, 0.5f, 50.0f), -0.5f);
  EXPECT_FLOAT_EQ(view_z_from_window_depth(0.0f, 0.5f, 50.0f), -50.0f);
}

// Reversed window depth keeps float precision at any near: at near 1e-7 and far 500 every depth
// from the near plane to 499 converts back within 1e-5 relative (the conventional near-0 depth
// read 1.0, background, for everything beyond about 0.6 units there).
TEST(ClusterLayout, WindowDepthKeepsItsPrecisionAtATinyNear) {
  const float n = 1e-7f, f = 500.0f;
  for (float z : {-1e-7f, -1e-4f, -0.3f, -7.0f, -120.0f, -499.0f}) {
    const float window = window_depth_from_view_z(z, n, f);
    ASSERT_GT(window, 0.0f) << z;
    EXPECT_NEAR(view_z_from_window_depth(window, n, f), z, 1e-5f * -z) << z;
  }
}

// And at the largest far planes (up to 3.4e38): near·far and d·(far − near) overflowed, which made
// every pixel beyond 3.4e38 / far background (window depth 0) and read every depth back as far.
TEST(ClusterLayout, WindowDepthHoldsAtTheLargestFarPlanes) {
  for (const auto& [n, f] : std::vector<std::pair<float, float>>{{0.1f, 3e38f}, {10.0f, 1e38f}, {1.0f, 1e37f}}) {
    for (float z : {-n, -2.0f * n, -100.0f, -1e6f, -1e30f}) {
      const float window = window_depth_from_view_z(z, n, f);
      ASSERT_GT(window, 0.0f) << n << " " << f << " " << z;
      ASSERT_LE(window, 1.0f) << n << " " << f << " " << z;
      EXPECT_NEAR(view_z_from_window_depth(window, n, f), z, 1e-5f * -z) << n << " " << f << " " << z;
    }
  }
}

// The ray-cast frame as window depth: a surface exactly on the far plane stays a surface (its
// depth was 0, the background's), one on the near plane reads 1, a miss the background.
TEST(ClusterLayout, WindowDepthOfASurfaceOnTheFarPlaneIsNotBackground) {
  Camera camera;
  camera.near_plane = 0.5f, camera.far_plane = 50.0f;
  DepthFrame frame;
  frame.width = 3, frame.height = 1;
  frame.view_z = {-50.0f, -0.5f, kNoSurfaceViewZ};
  const std::vector<float> depth = window_depth(frame, camera);
  const ClusterLayout layout = ClusterLayout::make(config_of(3, 1, 60, 0.5f, 50));
  EXPECT_GT(depth[0], 0.0f);
  EXPECT_EQ(pixel_distance(layout, depth[0], DepthFormat::Window), 50.0f);
  EXPECT_EQ(depth[1], 1.0f);
  EXPECT_EQ(depth[2], 0.0f);
  EXPECT_FALSE(pixel_distance(layout, depth[2], DepthFormat::Window));
}

TEST(ClusterLayout, NormalCellsCoverTheCubeMap) {
  EXPECT_EQ(normal_cell({1, 0, 0}), 0u * 9 + 4);
  EXPECT_EQ(normal_cell({-1, 0, 0}), 1u * 9 + 4);
  EXPECT_EQ(normal_cell({0, 1, 0}), 2u * 9 + 4);
  EXPECT_EQ(normal_cell({0, 0, -1}), 5u * 9 + 4);
  EXPECT_EQ(normal_cell({1, 0.9f, -0.9f}), 0u * 9 + 0 * 3 + 2);  // u = y high, v = z low
  std::set<std::uint32_t> seen;
  std::mt19937 random(3);
  std::normal_distribution<float> gauss;
  for (int i = 0; i < 20000; ++i) {
    const std::uint32_t cell = normal_cell(normalized(Vec3{gauss(random), gauss(random), gauss(random)}));
    ASSERT_LT(cell, kNormalCells);
    seen.insert(cell);
  }
  EXPECT_EQ(seen.size(), kNormalCells);
}

TEST(ClusterLayout, ClusterBoxContainsItsPixelsAndSlice) {
  auto c = config_of(100, 37, 70, 0.2f, 40);
  c.tile_width = 16;
  c.tile_height = 8;
  const auto layout = ClusterLayout::make(c);
  for (std::uint32_t y = 0; y < c.height; y += 3) {
    for (std::uint32_t x = 0; x < c.width; x += 3) {
      for (float d : {0.2f, 0.21f, 1.0f, 7.5f, 39.9f, 40.0f}) {
        const std::uint32_t key = layout.pack(layout.tile_of_pixel(x, y), slice_of_distance(layout, d), 0);
        const ClusterBox box = cluster_box(layout, key);
        const Vec3 p = pixel_view_position(layout, x, y, d);
        ASSERT_TRUE(box.min.x <= p.x && p.x <= box.max.x && box.min.y <= p.y && p.y <= box.max.y &&
                    box.min.z <= p.z && p.z <= box.max.z)
            << x << "," << y << " d=" << d;
      }
    }
  }
}

TEST(ClusterLayout, LightTouchesBoxIsTheSphereBoxTest) {
  const ClusterBox box{{0, 0, -2}, {1, 1, -1}};
  EXPECT_TRUE(light_touches_box({{0.5f, 0.5f, -1.5f}, 0.0f, {}}, box));  // centre inside, zero radius
  EXPECT_TRUE(light_touches_box({{2, 0.5f, -1.5f}, 1.0f, {}}, box));     // touches a face
  EXPECT_FALSE(light_touches_box({{2, 2, -1.5f}, 1.0f, {}}, box));       // near an edge, but outside
  EXPECT_TRUE(light_touches_box({{2, 2, -1.5f}, 1.5f, {}}, box));
}

}  // namespace
}  // namespace splatcl::cluster
