#pragma once
// Native C++ reference of every cluster stage: the correctness oracle in tests and the
// "reference" row of the benchmarks. Same definitions as the kernels, simplest algorithms.
#include <cstdint>
#include <vector>

#include "cluster/layout.hpp"
#include "cluster/types.hpp"

namespace splatcl::cluster {

// Key per pixel (kBackgroundKey where there is no geometry). `normals` is required (one per pixel)
// when the layout has normal bits, ignored otherwise.
std::vector<std::uint32_t> reference_keys(const ClusterLayout& layout, const std::vector<float>& depth,
                                          DepthFormat format, const std::vector<Vec3>* normals = nullptr);

// Unique valid keys ascending (std::sort + std::unique) and each pixel's index among them.
ClusterList reference_compact(const std::vector<std::uint32_t>& keys);

// cluster_box of every unique key.
std::vector<ClusterBox> reference_bounds(const ClusterLayout& layout, const std::vector<std::uint32_t>& unique_keys);

// Brute force: every light against every box, indices ascending; multithreaded over clusters.
LightLists reference_assign(const std::vector<ClusterBox>& boxes, const std::vector<PointLight>& lights);

}  // namespace splatcl::cluster
