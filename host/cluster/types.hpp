#pragma once
// Host-side data of the clustered-shading stage: vectors, lights, cluster boxes, and the two
// outputs (unique clusters with the per-pixel cluster index; per-cluster light lists).
#include <cstdint>
#include <vector>

#include "math/vec3.hpp"

namespace splatcl::cluster {

using splatcl::Vec3;

// Finite point light (thesis §2.4.3): no influence at distance ≥ radius.
struct PointLight {
  Vec3 center;  // view space when handed to the cluster stage
  float radius = 0;
  Vec3 color;  // RGB intensity, each channel in [0, 1]
  friend bool operator==(const PointLight&, const PointLight&) = default;
};

// Axis-aligned view-space box of one cluster.
struct ClusterBox {
  Vec3 min, max;
  friend bool operator==(const ClusterBox&, const ClusterBox&) = default;
};

// Unique clusters of a frame in ascending key order, and per pixel (row 0 = bottom) the index of
// its cluster in that list (kNoCluster for background).
struct ClusterList {
  std::vector<std::uint32_t> unique_keys;
  std::vector<std::uint32_t> pixel_cluster;
  friend bool operator==(const ClusterList&, const ClusterList&) = default;
};

// Light lists in the tiled-shading layout: cluster c owns indices[offsets[c] .. offsets[c] + counts[c]),
// light indices ascending within each cluster.
struct LightLists {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> counts;
  std::vector<std::uint32_t> indices;
  friend bool operator==(const LightLists&, const LightLists&) = default;
};

}  // namespace splatcl::cluster
