#include "splats/neighbors.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <flann/flann.hpp>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "runtime/error.hpp"
#include "splats/fit_device.hpp"

namespace splatcl::splats {

Neighborhoods find_neighbors(const std::vector<Vec4>& positions, unsigned k, const std::vector<Vec4>* normals,
                             float crease_cos) {
  if (k == 0) throw Error("the neighbourhood size k must be at least 1");
  const std::size_t n = positions.size();
  if (normals && normals->size() != n)
    throw Error(fmt::format("find_neighbors: {} normals for {} positions", normals->size(), n));
  const bool sheets = normals && crease_cos > -1.0f;
  Neighborhoods result;
  result.k = static_cast<std::uint32_t>(std::min<std::size_t>(k, n > 0 ? n - 1 : 0));
  result.kth_distance.assign(n, 0.0f);
  result.weight.assign(n, 0.0);
  if (result.k == 0) return result;
  const std::size_t kk = result.k;
  result.indices.resize(n * kk);
  // Vec4 rows with stride 4: FLANN sees 3 columns when the matrix stride says 16 bytes.
  flann::Matrix<float> data(const_cast<float*>(&positions[0].x), n, 3, sizeof(Vec4));
  flann::Index<flann::L2_Simple<float>> index(data, flann::KDTreeSingleIndexParams(10));
  index.buildIndex();
  constexpr std::size_t kBlock = 256;
  struct Scratch {
    std::vector<std::size_t> ids;
    std::vector<float> distances;
    std::vector<std::pair<float, std::uint32_t>> found;
  };
  std::vector<Scratch> scratch(worker_count(n, kBlock));
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);
  params.sorted = true;
  parallel_for(n, kBlock, [&](std::size_t i, std::size_t w) {
    auto& [ids, distances, found] = scratch[w];
    // The plain row first: a row with no neighbour on an opposed sheet is the plain graph's row
    // (ties at the k-th distance included); otherwise wider searches until k of its own are found.
    for (std::size_t want = kk + 1;; want = std::min(n, want * 4)) {
      ids.resize(want), distances.resize(want);
      flann::Matrix<float> query(const_cast<float*>(&positions[i].x), 1, 3, sizeof(Vec4));
      flann::Matrix<std::size_t> id_row(ids.data(), 1, want);
      flann::Matrix<float> distance_row(distances.data(), 1, want);
      index.knnSearch(query, id_row, distance_row, want, params);
      // Ties broken by index so the graph does not depend on the tree's visiting order.
      found.resize(want);
      for (std::size_t r = 0; r < want; ++r) found[r] = {distances[r], static_cast<std::uint32_t>(ids[r])};
      std::sort(found.begin(), found.end());
      // Drop the sample itself by index (duplicates have equal distance); if it is missing, the farthest.
      auto self = std::find_if(found.begin(), found.end(), [&](const auto& f) { return f.second == i; });
      if (self == found.end()) self = found.end() - 1;
      found.erase(self);
      if (!sheets) break;
      const Vec4 a = (*normals)[i];
      const auto same_sheet = [&](const std::pair<float, std::uint32_t>& f) {
        const Vec4 b = (*normals)[f.second];
        return !device::splat_opposed_sheets(a.x, a.y, a.z, b.x, b.y, b.z, crease_cos);
      };
      // Those of the sample's sheet first, each part still by distance.
      const auto others = std::stable_partition(found.begin(), found.end(), same_sheet);
      if (static_cast<std::size_t>(others - found.begin()) >= kk || want == n) break;
    }
    // A row filled from the other sheet is not in distance order: d is its farthest member's.
    float farthest = 0;
    for (std::size_t r = 0; r < kk; ++r) result.indices[i * kk + r] = found[r].second, farthest = std::max(farthest, found[r].first);
    const float d = std::sqrt(farthest);
    result.kth_distance[i] = d;
    result.weight[i] = std::numbers::pi * static_cast<double>(d) * static_cast<double>(d);
  });
  return result;
}

}  // namespace splatcl::splats
