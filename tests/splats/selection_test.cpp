// Greedy cover, optimisation and error metrics.
#include <gtest/gtest.h>

#include <random>

#include "splats/selection.hpp"

namespace splatcl::splats {
namespace {

Rows rows(const std::vector<std::vector<std::uint32_t>>& sets) {
  Rows r;
  for (const auto& s : sets) {
    r.items.insert(r.items.end(), s.begin(), s.end());
    r.offsets.push_back(static_cast<std::uint32_t>(r.items.size()));
  }
  return r;
}

// The thesis's procedure read literally: re-score every splat after each pick and take the
// largest, lowest index on ties.
std::vector<std::uint32_t> naive_greedy(const Rows& safe, std::size_t samples, const std::vector<double>& weight) {
  std::vector<bool> covered(samples, false);
  std::vector<std::uint32_t> picked;
  for (std::size_t left = samples; left > 0;) {
    double best = -1;
    std::uint32_t best_j = 0;
    std::size_t best_new = 0;
    for (std::uint32_t j = 0; j < safe.size(); ++j) {
      double s = 0;
      std::size_t fresh = 0;
      for (const std::uint32_t* m = safe.begin(j); m != safe.end(j); ++m)
        if (!covered[*m]) s += weight[*m], ++fresh;
      if (fresh && s > best) best = s, best_j = j, best_new = fresh;
    }
    picked.push_back(best_j);
    for (const std::uint32_t* m = safe.begin(best_j); m != safe.end(best_j); ++m) covered[*m] = true;
    left -= best_new;
  }
  return picked;
}

// Random instance shaped like the real one: splat j holds its own sample and some near ones.
Rows random_safe_sets(std::size_t n, std::mt19937& rng) {
  std::vector<std::vector<std::uint32_t>> sets(n);
  std::uniform_int_distribution<int> size(0, 12), offset(-15, 15);
  for (std::size_t j = 0; j < n; ++j) {
    sets[j].push_back(static_cast<std::uint32_t>(j));
    for (int r = size(rng); r > 0; --r) {
      const long m = static_cast<long>(j) + offset(rng);
      if (m >= 0 && m < static_cast<long>(n) && std::find(sets[j].begin(), sets[j].end(), m) == sets[j].end())
        sets[j].push_back(static_cast<std::uint32_t>(m));
    }
  }
  return rows(sets);
}

TEST(Selection, InverseIndexIsSortedBySplat) {
  const Rows safe = rows({{0, 2}, {1, 2}, {2, 0}});
  const Rows inverse = inverse_index(safe, 3);
  EXPECT_EQ(inverse.offsets, (std::vector<std::uint32_t>{0, 2, 3, 6}));
  EXPECT_EQ(inverse.items, (std::vector<std::uint32_t>{0, 2, 1, 0, 1, 2}));
}

TEST(Selection, LazyGreedyEqualsNaiveGreedy) {
  std::mt19937 rng(11);
  for (const std::size_t n : {1u, 2u, 17u, 500u, 3000u}) {
    const Rows safe = random_safe_sets(n, rng);
    std::vector<double> weight(n);
    // Few distinct weights: many exact ties exercise the lowest-index rule.
    std::uniform_int_distribution<int> w(1, 3);
    for (auto& x : weight) x = 0.25 * w(rng);
    EXPECT_EQ(greedy_cover(safe, inverse_index(safe, n), weight), naive_greedy(safe, n, weight)) << n;
  }
}

TEST(Selection, ZeroWeightsStillCover) {
  const Rows safe = rows({{0}});
  EXPECT_EQ(greedy_cover(safe, inverse_index(safe, 1), {0.0}), std::vector<std::uint32_t>{0});
  EXPECT_TRUE(greedy_cover(Rows{}, inverse_index(Rows{}, 0), {}).empty());
}

Neighborhoods chain_neighbors(std::size_t n, std::uint32_t k) {
  Neighborhoods nb;
  nb.k = k;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t r = 1; r <= k; ++r) nb.indices.push_back(static_cast<std::uint32_t>((i + r) % n));
  return nb;
}

TEST(Selection, RemovalIsSequential) {
  // Splats 0 and 1 hold the same samples: both kernels are empty, only one may go.
  const Rows safe = rows({{0, 1}, {0, 1}});
  const auto kept = optimise_selection({0, 1}, safe, inverse_index(safe, 2), {1.0, 1.0}, chain_neighbors(2, 1), 5);
  EXPECT_EQ(kept, std::vector<std::uint32_t>{1});
}

TEST(Selection, RelaxationSwapsToLessOverlap) {
  // Samples 0..5. Selected: 1 = {0,1,2,3} and 4 = {2,3,4,5} overlap on {2,3}. Splat 0 = {0,1,2}
  // covers splat 1's kernel {0,1} with overlap {2} only, so relaxation swaps 1 for 0.
  const Rows safe = rows({{0, 1, 2}, {1, 0, 2, 3}, {2}, {3}, {4, 2, 3, 5}, {5}});
  Neighborhoods nb;
  nb.k = 1;
  nb.indices = {1, 0, 3, 2, 5, 4};
  OptimiseStats stats;
  const auto result = optimise_selection({1, 4}, safe, inverse_index(safe, 6), std::vector<double>(6, 1.0), nb, 5, &stats);
  EXPECT_EQ(result, (std::vector<std::uint32_t>{0, 4}));
  EXPECT_EQ(stats.swaps, 1u);
}

TEST(Selection, OptimisationKeepsEverySampleCovered) {
  std::mt19937 rng(5);
  const std::size_t n = 2000;
  const Rows safe = random_safe_sets(n, rng);
  const Rows inverse = inverse_index(safe, n);
  std::vector<double> weight(n, 1.0);
  const auto greedy = greedy_cover(safe, inverse, weight);
  OptimiseStats stats;
  const auto optimised = optimise_selection(greedy, safe, inverse, weight, chain_neighbors(n, 10), 5, &stats);
  EXPECT_LE(optimised.size(), greedy.size());
  std::vector<bool> covered(n, false);
  for (const std::uint32_t j : optimised)
    for (const std::uint32_t* m = safe.begin(j); m != safe.end(j); ++m) covered[*m] = true;
  EXPECT_EQ(std::count(covered.begin(), covered.end(), false), 0);
  EXPECT_TRUE(std::is_sorted(optimised.begin(), optimised.end()));
}

TEST(Selection, ErrorMetrics) {
  Samples samples;
  samples.positions = {{0, 0, 0, 0}, {1, 0, 0.5f, 0}};
  samples.colors = {Rgba8{10, 20, 30, 255}, Rgba8{20, 20, 30, 255}};
  std::vector<SplatShape> splats(2);
  splats[0].center = {0, 0, 0.25f, 0};
  splats[0].normal = {0, 0, 1, 0};
  splats[1].center = {1, 0, 0.5f, 0};
  splats[1].normal = {0, 0, 1, 0};
  const Rows safe = rows({{0, 1}, {1}});
  const Rows inverse = inverse_index(safe, 2);
  const ErrorStats all = coverage_errors(samples, splats, inverse, nullptr);
  EXPECT_DOUBLE_EQ(all.mean, 0.125);  // sample 0: 0.25; sample 1: min(0.25, 0)
  EXPECT_DOUBLE_EQ(all.max, 0.25);
  EXPECT_DOUBLE_EQ(all.color[0], 2.5);  // sample 1's colour vs the mean of 10 and 20
  const std::vector<std::uint8_t> only_first{1, 0};
  const ErrorStats after = coverage_errors(samples, splats, inverse, &only_first);
  EXPECT_DOUBLE_EQ(after.mean, 0.25);
  EXPECT_EQ(after.uncovered, 0u);
}

}  // namespace
}  // namespace splatcl::splats
