#include "splats/selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "runtime/error.hpp"

namespace splatcl::splats {

Rows inverse_index(const Rows& safe, std::size_t samples) {
  Rows inverse;
  inverse.offsets.assign(samples + 1, 0);
  for (const std::uint32_t m : safe.items) ++inverse.offsets[m + 1];
  for (std::size_t m = 0; m < samples; ++m) inverse.offsets[m + 1] += inverse.offsets[m];
  inverse.items.resize(safe.items.size());
  std::vector<std::uint32_t> fill(inverse.offsets.begin(), inverse.offsets.end() - 1);
  for (std::size_t j = 0; j < safe.size(); ++j)
    for (const std::uint32_t* m = safe.begin(j); m != safe.end(j); ++m) inverse.items[fill[*m]++] = static_cast<std::uint32_t>(j);
  return inverse;
}

std::vector<std::uint32_t> greedy_cover(const Rows& safe, const Rows& inverse, const std::vector<double>& weight) {
  const std::size_t n = inverse.size();
  std::vector<std::uint8_t> covered(n, 0);
  // A sample that no safe set holds cannot be covered (a zero-size splat under the surface bound);
  // the cover is complete without it.
  std::size_t left = n;
  for (std::size_t m = 0; m < n; ++m)
    if (inverse.row_size(m) == 0) covered[m] = 1, --left;
  // Score and count of j's uncovered safe samples, summed in Q̄ order.
  auto score = [&](std::uint32_t j, std::size_t& uncovered) {
    double sum = 0;
    uncovered = 0;
    for (const std::uint32_t* m = safe.begin(j); m != safe.end(j); ++m)
      if (!covered[*m]) sum += weight[*m], ++uncovered;
    return sum;
  };
  // Max-heap on (score, -index): the highest score, then the lowest index.
  std::priority_queue<std::pair<double, std::int64_t>> heap;
  for (std::size_t j = 0; j < safe.size(); ++j) {
    std::size_t uncovered = 0;
    const double s = score(static_cast<std::uint32_t>(j), uncovered);
    if (uncovered) heap.emplace(s, -static_cast<std::int64_t>(j));
  }
  std::vector<std::uint32_t> picked;
  while (left > 0 && !heap.empty()) {
    const auto [stored, negative_j] = heap.top();
    heap.pop();
    const auto j = static_cast<std::uint32_t>(-negative_j);
    std::size_t uncovered = 0;
    const double fresh = score(j, uncovered);
    if (uncovered == 0) continue;
    if (fresh != stored) {  // scores only fall, so a stale entry goes back with its current score
      heap.emplace(fresh, negative_j);
      continue;
    }
    picked.push_back(j);
    for (const std::uint32_t* m = safe.begin(j); m != safe.end(j); ++m) covered[*m] = 1;
    left -= uncovered;
  }
  // Every coverable sample is in some safe set, so the cover always completes.
  if (left != 0) throw Error("greedy splat selection left coverable samples uncovered");
  return picked;
}

namespace {

class Optimiser {
 public:
  Optimiser(const Rows& safe, const Rows& inverse, const std::vector<double>& weight, const Neighborhoods& neighbors)
      : safe_(safe), inverse_(inverse), weight_(weight), neighbors_(neighbors), selected_(safe.size(), 0),
        count_(inverse.size(), 0), overlap_(safe.size(), 0.0), stamp_(inverse.size(), 0) {}

  void select(std::uint32_t j, bool on) {
    selected_[j] = on;
    for (const std::uint32_t* m = safe_.begin(j); m != safe_.end(j); ++m) on ? ++count_[*m] : --count_[*m];
  }

  std::vector<std::uint32_t> selection() const {
    std::vector<std::uint32_t> out;
    for (std::size_t j = 0; j < selected_.size(); ++j)
      if (selected_[j]) out.push_back(static_cast<std::uint32_t>(j));
    return out;
  }

  // max over selected s ∉ {skip1, skip2} sharing samples with j of Σ ω over the shared safe samples.
  double max_overlap(std::uint32_t j, std::uint32_t skip1, std::uint32_t skip2) {
    touched_.clear();
    for (const std::uint32_t* m = safe_.begin(j); m != safe_.end(j); ++m) {
      for (const std::uint32_t* s = inverse_.begin(*m); s != inverse_.end(*m); ++s) {
        if (!selected_[*s] || *s == skip1 || *s == skip2) continue;
        if (overlap_[*s] == 0.0) touched_.push_back(*s);
        overlap_[*s] += weight_[*m];
        if (overlap_[*s] == 0.0) overlap_[*s] = std::numeric_limits<double>::denorm_min();  // ω = 0 still touches
      }
    }
    double best = 0;
    for (const std::uint32_t s : touched_) best = std::max(best, overlap_[s]), overlap_[s] = 0.0;
    return best;
  }

  bool relax(std::uint32_t i) {
    kernel_.clear();
    for (const std::uint32_t* m = safe_.begin(i); m != safe_.end(i); ++m)
      if (count_[*m] == 1) kernel_.push_back(*m);
    std::uint32_t best = 0;
    double best_overlap = std::numeric_limits<double>::infinity();
    double base = -1;
    const std::uint32_t* row = neighbors_.row(i);
    for (std::uint32_t r = 0; r < neighbors_.k; ++r) {
      const std::uint32_t j = row[r];
      if (selected_[j]) continue;
      ++generation_;
      for (const std::uint32_t* m = safe_.begin(j); m != safe_.end(j); ++m) stamp_[*m] = generation_;
      if (!std::all_of(kernel_.begin(), kernel_.end(), [&](std::uint32_t m) { return stamp_[m] == generation_; })) continue;
      if (base < 0) base = max_overlap(i, i, i);
      const double o = max_overlap(j, i, j);
      if (o < best_overlap) best_overlap = o, best = j;
    }
    if (!(base >= 0 && best_overlap < base)) return false;
    select(i, false);
    select(best, true);
    return true;
  }

  bool remove_if_empty_kernel(std::uint32_t i) {
    for (const std::uint32_t* m = safe_.begin(i); m != safe_.end(i); ++m)
      if (count_[*m] == 1) return false;
    select(i, false);
    return true;
  }

 private:
  const Rows& safe_;
  const Rows& inverse_;
  const std::vector<double>& weight_;
  const Neighborhoods& neighbors_;
  std::vector<std::uint8_t> selected_;
  std::vector<std::uint32_t> count_;  // |V_m ∩ T'|
  std::vector<double> overlap_;
  std::vector<std::uint32_t> touched_, kernel_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
};

}  // namespace

std::vector<std::uint32_t> optimise_selection(std::vector<std::uint32_t> selected, const Rows& safe, const Rows& inverse,
                                              const std::vector<double>& weight, const Neighborhoods& neighbors,
                                              unsigned rounds, OptimiseStats* stats) {
  Optimiser optimiser(safe, inverse, weight, neighbors);
  for (const std::uint32_t j : selected) optimiser.select(j, true);
  OptimiseStats local;
  OptimiseStats& s = stats ? *stats : local;
  for (unsigned round = 0; round < rounds; ++round) {
    ++s.rounds;
    std::size_t changes = 0;
    for (const std::uint32_t i : optimiser.selection()) changes += optimiser.relax(i) ? (++s.swaps, 1) : 0;
    for (const std::uint32_t i : optimiser.selection()) changes += optimiser.remove_if_empty_kernel(i) ? (++s.removals, 1) : 0;
    if (changes == 0) break;
  }
  return optimiser.selection();
}

ErrorStats coverage_errors(const Samples& samples, const std::vector<SplatShape>& splats, const Rows& inverse,
                           const std::vector<std::uint8_t>* selected) {
  ErrorStats stats;
  double sum = 0, color_sum[3] = {0, 0, 0};
  for (std::size_t m = 0; m < inverse.size(); ++m) {
    const Vec4& p = samples.positions[m];
    double nearest = std::numeric_limits<double>::infinity();
    double mean_color[3] = {0, 0, 0};
    std::size_t holders = 0;
    for (const std::uint32_t* j = inverse.begin(m); j != inverse.end(m); ++j) {
      if (selected && !(*selected)[*j]) continue;
      const SplatShape& t = splats[*j];
      const double h = std::fabs(double{t.normal.x} * (double{p.x} - t.center.x) + double{t.normal.y} * (double{p.y} - t.center.y) +
                                 double{t.normal.z} * (double{p.z} - t.center.z));
      nearest = std::min(nearest, h);
      const Rgba8 c = samples.colors[*j];
      mean_color[0] += c.r, mean_color[1] += c.g, mean_color[2] += c.b;
      ++holders;
    }
    if (holders == 0) {
      ++stats.uncovered;
      continue;
    }
    sum += nearest;
    stats.max = std::max(stats.max, nearest);
    const Rgba8 c = samples.colors[m];
    const double own[3] = {static_cast<double>(c.r), static_cast<double>(c.g), static_cast<double>(c.b)};
    for (int ch = 0; ch < 3; ++ch) color_sum[ch] += std::fabs(mean_color[ch] / static_cast<double>(holders) - own[ch]);
  }
  const std::size_t counted = inverse.size() - stats.uncovered;
  if (counted) {
    stats.mean = sum / static_cast<double>(counted);
    for (int ch = 0; ch < 3; ++ch) stats.color[ch] = color_sum[ch] / static_cast<double>(counted);
  }
  return stats;
}

}  // namespace splatcl::splats
