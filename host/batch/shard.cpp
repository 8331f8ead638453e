#include "batch/shard.hpp"

#include <algorithm>
#include <charconv>

#include "runtime/error.hpp"

namespace splatcl::batch {

Shard parse_shard(const std::string& text) {
  auto fail = [&](const char* why) -> Shard { throw Error("bad shard '" + text + "': " + why); };
  const auto slash = text.find('/');
  if (slash == std::string::npos) return fail("expected i/N, e.g. 0/4");
  auto number = [](const std::string& digits, unsigned& out) {
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), out);
    return !digits.empty() && ec == std::errc() && end == digits.data() + digits.size();
  };
  Shard shard;
  if (!number(text.substr(0, slash), shard.index) || !number(text.substr(slash + 1), shard.count))
    return fail("expected i/N with non-negative integers, e.g. 0/4");
  if (shard.count == 0) return fail("N must be at least 1");
  if (shard.index >= shard.count) return fail("i must be below N (shards are numbered 0 to N-1)");
  return shard;
}

std::vector<ModelEntry> select_shard(std::vector<ModelEntry> models, const Shard& shard) {
  std::sort(models.begin(), models.end(), [](const ModelEntry& a, const ModelEntry& b) { return a.id < b.id; });
  std::vector<ModelEntry> selected;
  for (std::size_t rank = 0; rank < models.size(); ++rank)
    if (rank % shard.count == shard.index) selected.push_back(std::move(models[rank]));
  return selected;
}

}  // namespace splatcl::batch
