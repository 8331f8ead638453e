#pragma once
// Host-side data of the clustered-shading stage: vectors, lights, cluster boxes, and the two
// outputs (unique clusters with the per-pixel cluster index; per-cluster light lists).
#include <cmath>
#include <cstdint>
#include <vector>

namespace splatcl::cluster {

struct Vec3 {
  float x = 0, y = 0, z = 0;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
  friend Vec3 operator*(float s, Vec3 a) { return a * s; }
  friend bool operator==(Vec3 a, Vec3 b) = default;
};
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return a * (1.0f / length(a)); }

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
