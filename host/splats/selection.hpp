#pragma once
// Choosing the splats (the splat thesis §2.2.3, §2.2.4, §3.2): greedy cover of the samples by the safe sets Q̄_j,
// scored by the ω-weighted sum of their uncovered samples, then rounds of relaxation and removal;
// and the error metrics before and after selection.
//
// Interpretation choices: ties in the greedy pick go to the lowest splat index; the lazy priority
// queue recomputes a popped splat's score from scratch (same summation order every time), so it
// picks exactly what "re-sort and take the largest" picks. Relaxation and removal visit the
// splats selected at the start of the pass in index order, applying each change at once; a
// relaxation candidate's maximum overlap excludes the splat it would replace; among equally good
// candidates the nearest neighbour (first in N_k) wins.
#include <cstdint>
#include <vector>

#include "splats/fit.hpp"
#include "splats/neighbors.hpp"

namespace splatcl::splats {

// V_m: for every sample, the splats whose safe set holds it, in increasing splat index.
Rows inverse_index(const Rows& safe, std::size_t samples);

// Greedy cover of every sample that some safe set holds; returns the picked splats in pick order.
std::vector<std::uint32_t> greedy_cover(const Rows& safe, const Rows& inverse, const std::vector<double>& weight);

struct OptimiseStats {
  unsigned rounds = 0;       // rounds run (stops early when a round changes nothing)
  std::size_t swaps = 0;     // relaxation swaps over all rounds
  std::size_t removals = 0;  // removed splats over all rounds
};

// Relaxation and removal rounds on `selected` (any order in; increasing index out). `neighbors`
// gives the splat neighbourhood N_k(t_i) = splats started at N_k(p_i).
std::vector<std::uint32_t> optimise_selection(std::vector<std::uint32_t> selected, const Rows& safe, const Rows& inverse,
                                              const std::vector<double>& weight, const Neighborhoods& neighbors,
                                              unsigned rounds, OptimiseStats* stats = nullptr);

// Mean and maximum over the samples of the distance |n_j · (p_m − c_j)| to the nearest splat among
// those whose safe set holds m (all splats, or only the selected ones), and the mean absolute
// per-channel difference between a sample's colour and the mean colour of those splats (a splat's
// colour is its start sample's). Samples no considered splat holds are counted in `uncovered`.
struct ErrorStats {
  double mean = 0, max = 0;
  double color[3] = {0, 0, 0};
  std::size_t uncovered = 0;
};
ErrorStats coverage_errors(const Samples& samples, const std::vector<SplatShape>& splats, const Rows& inverse,
                           const std::vector<std::uint8_t>* selected);

}  // namespace splatcl::splats
