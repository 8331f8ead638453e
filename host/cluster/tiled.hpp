#pragma once
// Tiled light lists, the baseline the clustered lists are measured against (the presenter's
// "tiled" shading): one list per screen tile of the layout, holding every light that touches the
// view-space box of the tile's frustum between the nearest and farthest of its covered pixels.
// Computed on the host, beside the clustered stages' references (reference.hpp).
#include <cstdint>
#include <vector>

#include "cluster/layout.hpp"
#include "cluster/types.hpp"

namespace splatcl::cluster {

struct TiledLights {
  std::vector<std::uint32_t> pixel_list;  // per pixel its tile's list, kNoCluster where uncovered
  LightLists lists;                       // one per tile; empty for a tile with no covered pixel
};

// `view_z`: view-space z per pixel (row 0 = bottom), as DepthFormat::ViewZ (0 = background).
TiledLights tiled_light_lists(const ClusterLayout& layout, const std::vector<float>& view_z,
                              const std::vector<PointLight>& lights);

}  // namespace splatcl::cluster
