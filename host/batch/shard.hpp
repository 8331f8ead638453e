#pragma once
// Spreading a batch over machines: shard i of N takes the models whose rank in id order is
// congruent to i modulo N. The assignment depends only on the set of ids, so every shard of a
// run computes the same partition independently, and the N shards together cover every model
// exactly once with sizes differing by at most one.
#include <string>
#include <vector>

#include "batch/manifest.hpp"

namespace splatcl::batch {

struct Shard {
  unsigned index = 0, count = 1;
  bool whole() const { return count == 1; }
};

// Parses "i/N" (0 <= i < N). Throws Error "bad shard 'TEXT': ..." otherwise.
Shard parse_shard(const std::string& text);

// The models of `shard`, in id order. `models` need not be sorted.
std::vector<ModelEntry> select_shard(std::vector<ModelEntry> models, const Shard& shard);

}  // namespace splatcl::batch
