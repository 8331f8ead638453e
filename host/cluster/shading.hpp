#pragma once
// Host-side deferred shading of a depth frame with many finite point lights (Tegelaers
// §2.4): the reference the GL presenter's final shading will be checked against, and the
// check that clustered light lists lose nothing (clustered shading equals brute-force shading).
//
//   L_o = Σ_k albedo/π · (π·i_k) · f(d_k) · max(0, n·l_k),   f(d) = clamp(1 − (d/r)², 0, 1)
//
// The falloff is our reading of the thesis's garbled "(l/r)² clamped to [0,1]" (1 at the light,
// exactly 0 at r). Intensities are pre-multiplied by π (our choice: the thesis gives no scale) so that a light
// touching a surface head-on gives albedo · i.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "cluster/layout.hpp"
#include "cluster/types.hpp"

namespace splatcl::cluster {

// Falloff f(d) for a light of radius r.
float light_falloff(float distance, float radius);

// RGB per pixel (row 0 = bottom), 0 for background. `view_z` and `normals` as produced by the
// ray caster (DepthFormat::ViewZ). Shades with each pixel's cluster light list.
std::vector<float> shade_clustered(const ClusterLayout& layout, const std::vector<float>& view_z,
                                   const std::vector<Vec3>& normals, const std::vector<PointLight>& lights,
                                   const ClusterList& clusters, const LightLists& lists, Vec3 albedo);

// Rows shaded so far and the frame's rows, for a progress line.
using RowProgress = std::function<void(std::size_t rows_done, std::size_t rows)>;

// The same with every light for every pixel: pixels x lights evaluations (minutes with 3 x 10^5
// lights at 1920x1080 on 2 cores), so it reports its rows to `progress` when set.
std::vector<float> shade_brute_force(const ClusterLayout& layout, const std::vector<float>& view_z,
                                     const std::vector<Vec3>& normals, const std::vector<PointLight>& lights,
                                     Vec3 albedo, const RowProgress& progress = {});

}  // namespace splatcl::cluster
