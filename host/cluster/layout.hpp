#pragma once
// Cluster grid of one frame (tiles × exponential depth slices × optional normal cells), the key
// packing, and the per-pixel arithmetic shared by the kernels, the native reference and the tests
// (what kernels and reference compute bit for bit alike is written once, in kernels/cluster_layout.h).
// Conventions: row 0 of every per-pixel buffer is the BOTTOM row (OpenGL window coordinates);
// view space looks down −z; distances d = −z_view are positive.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "cluster/types.hpp"
#include "core/camera.hpp"

namespace splatcl::cluster {

// Key of a pixel with no geometry; sorts after every valid key (see ClusterLayout::tile_bits).
inline constexpr std::uint32_t kBackgroundKey = 0xFFFFFFFFu;
// Cluster index of a background pixel.
inline constexpr std::uint32_t kNoCluster = 0xFFFFFFFFu;
// What the test-scene ray caster writes for a pixel whose ray hits nothing in [near, far].
inline constexpr float kBackgroundViewZ = 0.0f;

// Normal-cone variant (Olsson et al. 2012, not in the thesis): the view-space normal is quantised
// onto a cube map with 3×3 cells per face, 54 directions, stored in the low 6 bits of the key.
inline constexpr unsigned kNormalKeyBits = 6;
inline constexpr std::uint32_t kNormalCells = 54;

// Largest tile side (pixels) of any layout.
inline constexpr std::uint32_t kMaxTileSide = 4096;
// Largest tile (pixels) that the per-tile sort compaction accepts: its buffers live in private or
// local memory.
inline constexpr std::uint32_t kMaxSortTilePixels = 4096;
// Largest (slice, normal) value space per tile that the bitmask compaction accepts (bits).
inline constexpr unsigned kMaxBitmaskLowBits = 16;

// What a depth buffer holds.
enum class DepthFormat {
  ViewZ,   // view-space z: negative in front of the camera; outside [−far, −near] or NaN = background
  Window,  // reversed window depth in (0, 1] (near 1, far 0) with the perspective projection of (near, far); ≤ 0 = background
};

struct ClusterConfig {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t tile_width = 32;
  std::uint32_t tile_height = 32;
  float near_plane = 0.1f;
  float far_plane = 100.0f;
  float fov_y = 1.04719755f;  // vertical field of view, radians
  bool normal_bits = false;   // add the 6 normal-cone bits to the key
};

// The derived grid. Key = (tileId << (slice_bits + normal_bits)) | (slice << normal_bits) | normalCell,
// tileId = j · tiles_x + i. tile_bits is chosen so that tile_count ≤ 2^tile_bits − 1: no valid key
// has all of its key_bits low bits set, so a sort on only those bits still puts background last.
struct ClusterLayout {
  ClusterConfig config;
  std::uint32_t tiles_x = 0, tiles_y = 0, tile_count = 0;
  std::uint32_t slice_count = 0;  // S_z
  unsigned tile_bits = 0, slice_bits = 0, normal_bits = 0, key_bits = 0;
  double q = 0;                // slice ratio 1 + 2·tan(fovY/2)/S_y
  float tan_half_x = 0, tan_half_y = 0;
  float ln_near = 0, inv_ln_q = 0;          // for the first guess of the slice formula
  float two_over_width = 0, two_over_height = 0;
  float near_over_far = 0, far_share = 0;  // window-depth conversion: near/far, 1 − near/far
  float padding_scale = 0;                 // cluster-box padding per unit of far distance
  std::vector<float> slice_boundaries;     // d_k = near·q^k for k = 0..S_z (last one ≥ far)

  // Validates the config (throws Error with a one-line reason) and derives the grid.
  static ClusterLayout make(const ClusterConfig& config);

  std::size_t pixel_count() const { return std::size_t{config.width} * config.height; }
  unsigned low_bits() const { return slice_bits + normal_bits; }  // bits below the tile id
  std::uint32_t tile_of_pixel(std::uint32_t x, std::uint32_t y) const {
    return y / config.tile_height * tiles_x + x / config.tile_width;
  }
  std::uint32_t pack(std::uint32_t tile, std::uint32_t slice, std::uint32_t normal_cell) const {
    return (tile << low_bits()) | (slice << normal_bits) | normal_cell;
  }
  struct KeyFields {
    std::uint32_t tile_x, tile_y, slice, normal_cell;
  };
  KeyFields unpack(std::uint32_t key) const;
};

// View distance (−z_view) of a depth sample, or nothing for background. Window depth is converted
// with near·far / (far − depth·(far − near)) and clamped into [near, far].
std::optional<float> pixel_distance(const ClusterLayout& layout, float depth, DepthFormat format);

// Depth slice of a view distance in [near, far]: k = floor(ln(d/near) / ln(q)), evaluated exactly
// as the largest k < S_z with d_k ≤ d.
std::uint32_t slice_of_distance(const ClusterLayout& layout, float distance);

// Cube-map cell (0..53) of a view-space normal: face = 2·axis + (major component < 0), then the
// two other components (in x, y, z order) divided by |major| fall into thirds of [−1, 1].
std::uint32_t normal_cell(Vec3 normal);

// View-space z of a reversed window depth in [0, 1] (1 at the near plane, 0 at the far one: the
// presenter's depth buffer) under the perspective projection of (near, far).
float view_z_from_window_depth(float depth, float near_plane, float far_plane);
// The inverse: reversed window depth in [0, 1] of a view-space z in [−far, −near].
float window_depth_from_view_z(float view_z, float near_plane, float far_plane);

// View-space position of the centre of pixel (x, y) (row 0 = bottom) at view distance `distance`.
Vec3 pixel_view_position(const ClusterLayout& layout, std::uint32_t x, std::uint32_t y, float distance);

// View-space box of cluster (tile, slice): the tile's sub-frustum between d_k and d_k+1, padded by
// kBoundsPadding · max(1, tan) relative to the far distance d_k+1, which covers the float rounding
// of pixel positions reconstructed from (pixel, distance).
inline constexpr float kBoundsPadding = 1e-5f;
ClusterBox cluster_box(const ClusterLayout& layout, std::uint32_t key);

// Sphere–box overlap: squared distance from the light centre to the box ≤ radius².
bool light_touches_box(const PointLight& light, const ClusterBox& box);

// Cluster config of a frame seen by `camera`.
ClusterConfig cluster_config(const Camera& camera, std::uint32_t width, std::uint32_t height,
                             std::uint32_t tile_width = 32, std::uint32_t tile_height = 32, bool normal_bits = false);

}  // namespace splatcl::cluster
