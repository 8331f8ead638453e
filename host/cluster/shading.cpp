#include "cluster/shading.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <span>

#include "core/parallel.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

// Shades pixel rows in parallel; light_span(p) gives the lights (indices) to evaluate at pixel p.
// `progress` (when set) hears the rows done, one call at a time, the last with every row.
template <class LightSpan>
std::vector<float> shade_rows(const ClusterLayout& layout, const std::vector<float>& view_z,
                              const std::vector<Vec3>& normals, const std::vector<PointLight>& lights, Vec3 albedo,
                              LightSpan light_span, const RowProgress& progress = {}) {
  const std::uint32_t width = layout.config.width, height = layout.config.height;
  if (view_z.size() != layout.pixel_count() || normals.size() != layout.pixel_count())
    throw Error("shading: depth or normal buffer does not match the frame size");
  std::vector<float> rgb(layout.pixel_count() * 3, 0.0f);
  auto shade_range = [&](std::uint32_t row_begin, std::uint32_t row_end) {
    for (std::uint32_t y = row_begin; y < row_end; ++y)
      for (std::uint32_t x = 0; x < width; ++x) {
        const std::size_t p = std::size_t{y} * width + x;
        const auto distance = pixel_distance(layout, view_z[p], DepthFormat::ViewZ);
        if (!distance) continue;
        const Vec3 position = pixel_view_position(layout, x, y, *distance);
        Vec3 sum{};
        for (const std::uint32_t index : light_span(p)) {
          const PointLight& light = lights[index];
          const Vec3 to_light = light.center - position;
          const float d = length(to_light);
          const float falloff = light_falloff(d, light.radius);
          if (falloff <= 0.0f || d <= 0.0f) continue;
          const float cos_theta = std::max(0.0f, dot(normals[p], to_light * (1.0f / d)));
          // albedo/π · (π·i) · f · cosθ: the π factors cancel.
          sum = sum + light.color * (falloff * cos_theta);
        }
        rgb[3 * p + 0] = albedo.x * sum.x;
        rgb[3 * p + 1] = albedo.y * sum.y;
        rgb[3 * p + 2] = albedo.z * sum.z;
      }
  };
  std::mutex progress_mutex;
  std::size_t rows_done = 0;
  parallel_for(height, 4, [&](std::size_t y, std::size_t) {
    shade_range(static_cast<std::uint32_t>(y), static_cast<std::uint32_t>(y + 1));
    if (!progress) return;
    std::lock_guard lock(progress_mutex);
    progress(++rows_done, height);
  });
  return rgb;
}

}  // namespace

float light_falloff(float distance, float radius) {
  if (!(radius > 0.0f)) return 0.0f;
  const float ratio = distance / radius;
  return std::clamp(1.0f - ratio * ratio, 0.0f, 1.0f);
}

std::vector<float> shade_clustered(const ClusterLayout& layout, const std::vector<float>& view_z,
                                   const std::vector<Vec3>& normals, const std::vector<PointLight>& lights,
                                   const ClusterList& clusters, const LightLists& lists, Vec3 albedo) {
  if (clusters.pixel_cluster.size() != layout.pixel_count())
    throw Error("shading: cluster index buffer does not match the frame size");
  return shade_rows(layout, view_z, normals, lights, albedo, [&](std::size_t p) {
    const std::uint32_t c = clusters.pixel_cluster[p];
    if (c == kNoCluster) return std::span<const std::uint32_t>{};
    return std::span<const std::uint32_t>(lists.indices.data() + lists.offsets[c], lists.counts[c]);
  });
}

std::vector<float> shade_brute_force(const ClusterLayout& layout, const std::vector<float>& view_z,
                                     const std::vector<Vec3>& normals, const std::vector<PointLight>& lights,
                                     Vec3 albedo, const RowProgress& progress) {
  std::vector<std::uint32_t> all(lights.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  return shade_rows(layout, view_z, normals, lights, albedo,
                    [&](std::size_t) { return std::span<const std::uint32_t>(all); }, progress);
}

}  // namespace splatcl::cluster
