// Sharding: parsing i/N, and shards 0..N-1 covering every model exactly once, balanced, whatever
// the order the models were listed in.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "batch/shard.hpp"
#include "runtime/error.hpp"

namespace splatcl::batch {
namespace {

std::vector<ModelEntry> models_named(std::size_t n, std::mt19937& rng) {
  std::vector<ModelEntry> models(n);
  for (std::size_t i = 0; i < n; ++i) {
    models[i].id = fmt::format("m{}-{}", rng() % 100000, i);
    models[i].input = models[i].id + ".obj";
  }
  return models;
}

TEST(Shard, ParsesIndexOverCount) {
  const Shard whole = parse_shard("0/1");
  EXPECT_EQ(whole.index, 0u);
  EXPECT_EQ(whole.count, 1u);
  EXPECT_TRUE(whole.whole());
  const Shard last = parse_shard("99/100");
  EXPECT_EQ(last.index, 99u);
  EXPECT_EQ(last.count, 100u);
  EXPECT_FALSE(last.whole());
}

TEST(Shard, RejectsBadSpecsWithOneLine) {
  auto message = [](const std::string& text) {
    try {
      parse_shard(text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message("4/4"), "bad shard '4/4': i must be below N (shards are numbered 0 to N-1)");
  EXPECT_EQ(message("1/0"), "bad shard '1/0': N must be at least 1");
  EXPECT_EQ(message("3"), "bad shard '3': expected i/N, e.g. 0/4");
  for (const std::string bad : {"", "/", "a/b", "-1/2", "1/2/3", " 1/2", "1/2x", "1.5/4", "99999999999/1"})
    EXPECT_EQ(message(bad).rfind("bad shard '" + bad + "': ", 0), 0u) << bad << ": " << message(bad);
}

TEST(Shard, ShardsCoverEveryModelExactlyOnceAndBalanced) {
  std::mt19937 rng(7);
  for (std::size_t n : {0u, 1u, 2u, 5u, 17u, 64u, 101u}) {
    for (unsigned count : {1u, 2u, 3u, 8u, 13u, 200u}) {
      const auto models = models_named(n, rng);
      std::map<std::string, int> seen;
      std::size_t smallest = n, largest = 0;
      for (unsigned index = 0; index < count; ++index) {
        auto shuffled = models;
        std::shuffle(shuffled.begin(), shuffled.end(), rng);  // listing order must not matter
        const auto shard = select_shard(shuffled, {index, count});
        EXPECT_TRUE(std::is_sorted(shard.begin(), shard.end(), [](const ModelEntry& a, const ModelEntry& b) { return a.id < b.id; }));
        for (const auto& m : shard) ++seen[m.id];
        smallest = std::min(smallest, shard.size());
        largest = std::max(largest, shard.size());
      }
      ASSERT_EQ(seen.size(), n) << n << " models, " << count << " shards";
      for (const auto& [id, times] : seen) EXPECT_EQ(times, 1) << id;
      EXPECT_LE(largest - smallest, 1u) << n << " models, " << count << " shards";
    }
  }
}

TEST(Shard, AssignmentIsByRankInIdOrder) {
  std::vector<ModelEntry> models(5);
  const char* ids[] = {"e", "a", "d", "b", "c"};
  for (int i = 0; i < 5; ++i) models[static_cast<std::size_t>(i)].id = ids[i];
  auto ids_of = [](const std::vector<ModelEntry>& list) {
    std::vector<std::string> out;
    for (const auto& m : list) out.push_back(m.id);
    return out;
  };
  EXPECT_EQ(ids_of(select_shard(models, {0, 2})), (std::vector<std::string>{"a", "c", "e"}));
  EXPECT_EQ(ids_of(select_shard(models, {1, 2})), (std::vector<std::string>{"b", "d"}));
  EXPECT_EQ(ids_of(select_shard(models, {0, 1})), (std::vector<std::string>{"a", "b", "c", "d", "e"}));
}

}  // namespace
}  // namespace splatcl::batch
