#pragma once
// Exact k-nearest-neighbour graph of the samples (the splat thesis §2.2.1), by a FLANN single kd-tree:
// N_k(p_i) excludes p_i, sorted by distance then index; d_i = distance to the k-th neighbour;
// ω_i = π d_i².
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace splatcl::splats {

struct Neighborhoods {
  std::uint32_t k = 0;                  // min(requested k, samples - 1)
  std::vector<std::uint32_t> indices;   // samples × k, row i = N_k(p_i)
  std::vector<float> kth_distance;      // d_i
  std::vector<double> weight;           // ω_i
  const std::uint32_t* row(std::size_t i) const { return indices.data() + i * k; }
};

// With normals (one per position) and a crease cosine above -1: the k nearest among the samples
// not on an opposed sheet (splat_opposed_sheets, kernels/splat_fit.h), those on one filling the
// row only when fewer than k others exist. An extension: on a plate thinner than the sample
// spacing, about half of the plain k nearest lie on the other side, so growth on one side walked
// a sparse tree of its own side, each splat's covered set held half the samples inside it, and
// selection stacked splats up to 37 deep. Throws Error when k is 0.
Neighborhoods find_neighbors(const std::vector<Vec4>& positions, unsigned k, const std::vector<Vec4>* normals = nullptr,
                             float crease_cos = -2.0f);

}  // namespace splatcl::splats
