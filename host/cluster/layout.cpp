#include "cluster/layout.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <string>

#include "runtime/error.hpp"

namespace splatcl::cluster {

// The distances, the normal cell, the cluster box and the sphere–box test: one source with the
// kernels.
namespace device {
using uint = std::uint32_t;
#include "../../kernels/cluster_layout.h"
DEFINE_CLUSTER_SPHERE_TOUCHES_BOX(sphere_touches_box, float, bool)
}  // namespace device

namespace {

// Thinner slices than this would put the key kernel's fast first guess of the slice more than
// 0.2 slices off (see slice_of_distance in kernels/cluster.cl): a narrower view takes slices this
// thick, deeper than its tiles are wide (clusters still bound their pixels; lists only get longer).
constexpr double kMinSliceRatioExcess = 2e-4;

std::string dims(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "x" + std::to_string(b); }

}  // namespace

ClusterLayout ClusterLayout::make(const ClusterConfig& config) {
  if (config.width == 0 || config.height == 0)
    throw Error("cluster frame size " + dims(config.width, config.height) + " is empty");
  if (config.tile_width == 0 || config.tile_height == 0)
    throw Error("cluster tile size " + dims(config.tile_width, config.tile_height) + " has a zero side");
  if (config.tile_width > kMaxTileSide || config.tile_height > kMaxTileSide)
    throw Error("cluster tile size " + dims(config.tile_width, config.tile_height) + " exceeds " +
                std::to_string(kMaxTileSide) + " pixels per side");
  if (std::uint64_t{config.width} * config.height > 0x7FFFFFFFu)
    throw Error("cluster frame size " + dims(config.width, config.height) + " exceeds 2^31 pixels");
  if (!(std::isfinite(config.near_plane) && config.near_plane >= FLT_MIN))
    throw Error("cluster near plane must be a positive finite distance, got " + std::to_string(config.near_plane));
  if (!(std::isfinite(config.far_plane) && config.far_plane > config.near_plane))
    throw Error("cluster far plane " + std::to_string(config.far_plane) + " must be beyond the near plane " +
                std::to_string(config.near_plane));
  if (!(config.fov_y > 0 && config.fov_y < 3.1415f))
    throw Error("cluster vertical field of view must be in (0, pi) radians, got " + std::to_string(config.fov_y));

  ClusterLayout layout;
  layout.config = config;
  layout.tiles_x = (config.width + config.tile_width - 1) / config.tile_width;
  layout.tiles_y = (config.height + config.tile_height - 1) / config.tile_height;
  layout.tile_count = layout.tiles_x * layout.tiles_y;

  const double tan_half_y = std::tan(0.5 * double{config.fov_y});
  const double aspect = static_cast<double>(config.width) / static_cast<double>(config.height);
  // Refused before (a field of view below ~0.1 degree at 640x480): brute-force and tiled shading,
  // which use no slices, were refused with it.
  layout.q = std::max(1.0 + 2.0 * tan_half_y / layout.tiles_y, 1.0 + kMinSliceRatioExcess);
  const double ln_q = std::log(layout.q);
  const double slices = std::ceil(std::log(double{config.far_plane} / double{config.near_plane}) / ln_q);
  layout.slice_count = static_cast<std::uint32_t>(std::max(1.0, slices));

  layout.tile_bits = static_cast<unsigned>(std::bit_width(layout.tile_count));
  layout.slice_bits = static_cast<unsigned>(std::bit_width(layout.slice_count - 1));
  layout.normal_bits = config.normal_bits ? kNormalKeyBits : 0;
  const unsigned key_bits = layout.tile_bits + layout.slice_bits + layout.normal_bits;
  if (key_bits > 32)
    throw Error("too many tiles (" + std::to_string(layout.tile_count) + ") and depth slices (" +
                std::to_string(layout.slice_count) + ") for 32-bit cluster keys: " + std::to_string(key_bits) +
                " bits needed; use larger tiles or a larger near/far ratio");
  layout.key_bits = key_bits;

  layout.tan_half_y = static_cast<float>(tan_half_y);
  layout.tan_half_x = static_cast<float>(aspect * tan_half_y);
  layout.ln_near = static_cast<float>(std::log(double{config.near_plane}));
  layout.inv_ln_q = static_cast<float>(1.0 / ln_q);
  layout.two_over_width = 2.0f / static_cast<float>(config.width);
  layout.two_over_height = 2.0f / static_cast<float>(config.height);
  layout.near_over_far = config.near_plane / config.far_plane;
  layout.far_share = 1.0f - layout.near_over_far;
  layout.padding_scale = kBoundsPadding * std::max({1.0f, layout.tan_half_x, layout.tan_half_y});

  layout.slice_boundaries.resize(layout.slice_count + 1);
  for (std::uint32_t k = 0; k <= layout.slice_count; ++k)
    layout.slice_boundaries[k] = static_cast<float>(double{config.near_plane} * std::pow(layout.q, double(k)));
  layout.slice_boundaries.front() = config.near_plane;
  layout.slice_boundaries.back() = std::max(layout.slice_boundaries.back(), config.far_plane);
  return layout;
}

ClusterLayout::KeyFields ClusterLayout::unpack(std::uint32_t key) const {
  const std::uint32_t tile = key >> low_bits();
  return {tile % tiles_x, tile / tiles_x, (key >> normal_bits) & ((1u << slice_bits) - 1u),
          key & ((1u << normal_bits) - 1u)};
}

std::optional<float> pixel_distance(const ClusterLayout& layout, float depth, DepthFormat format) {
  const ClusterConfig& c = layout.config;
  const float distance = format == DepthFormat::Window
                             ? device::cluster_window_distance(depth, c.near_plane, c.far_plane,
                                                               layout.near_over_far, layout.far_share)
                             : device::cluster_view_distance(depth, c.near_plane, c.far_plane);
  if (distance < 0.0f) return std::nullopt;  // a valid distance is at least near > 0
  return distance;
}

std::uint32_t slice_of_distance(const ClusterLayout& layout, float distance) {
  const auto first = layout.slice_boundaries.begin();
  const auto after = std::upper_bound(first, first + layout.slice_count, distance);
  return static_cast<std::uint32_t>(std::max<std::ptrdiff_t>(after - first - 1, 0));
}

std::uint32_t normal_cell(Vec3 normal) { return device::cluster_normal_cell(normal.x, normal.y, normal.z); }

float view_z_from_window_depth(float depth, float near_plane, float far_plane) {
  const float near_over_far = near_plane / far_plane;
  return -device::cluster_window_to_distance(depth, near_plane, near_over_far, 1.0f - near_over_far);
}

float window_depth_from_view_z(float view_z, float near_plane, float far_plane) {
  // near·(far − d) / (d·(far − near)) as two factors of at most 1: d·(far − near) overflowed for
  // far planes beyond 3.4e38 / d, which made every such pixel background.
  const float distance = -view_z;
  return (near_plane / distance) * ((far_plane - distance) / (far_plane - near_plane));
}

Vec3 pixel_view_position(const ClusterLayout& layout, std::uint32_t x, std::uint32_t y, float distance) {
  const float ndc_x = (static_cast<float>(x) + 0.5f) * layout.two_over_width - 1.0f;
  const float ndc_y = (static_cast<float>(y) + 0.5f) * layout.two_over_height - 1.0f;
  return {ndc_x * distance * layout.tan_half_x, ndc_y * distance * layout.tan_half_y, -distance};
}

ClusterBox cluster_box(const ClusterLayout& layout, std::uint32_t key) {
  const ClusterConfig& c = layout.config;
  const device::ClusterGrid grid = {c.width, c.height, c.tile_width, c.tile_height, layout.tiles_x, layout.low_bits(),
                                    layout.normal_bits, (1u << layout.slice_bits) - 1u, layout.two_over_width,
                                    layout.two_over_height, layout.tan_half_x, layout.tan_half_y,
                                    layout.padding_scale};
  float lo[3], hi[3];
  device::cluster_key_box(grid, key, layout.slice_boundaries.data(), lo, hi);
  return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

bool light_touches_box(const PointLight& light, const ClusterBox& box) {
  return device::sphere_touches_box(box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z,
                                    light.center.x, light.center.y, light.center.z, light.radius);
}

ClusterConfig cluster_config(const Camera& camera, std::uint32_t width, std::uint32_t height, std::uint32_t tile_width,
                             std::uint32_t tile_height, bool normal_bits) {
  ClusterConfig config;
  config.width = width;
  config.height = height;
  config.tile_width = tile_width;
  config.tile_height = tile_height;
  config.near_plane = camera.near_plane;
  config.far_plane = camera.far_plane;
  config.fov_y = camera.fov_y;
  config.normal_bits = normal_bits;
  return config;
}

}  // namespace splatcl::cluster
