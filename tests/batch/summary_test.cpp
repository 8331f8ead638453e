// Summaries: counts, shard indices, and merging shard summaries with every inconsistency refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>
#include <vector>

#include "batch/summary.hpp"
#include "runtime/error.hpp"

namespace splatcl::batch {
namespace {

nlohmann::json shard_summary(unsigned index, unsigned count, const std::vector<std::string>& ids, const std::string& checksum = "c0ffee",
                             std::size_t total = 5) {
  RunInfo info;
  info.manifest_checksum = checksum;
  info.manifest_models = total;
  info.device = "pthread-test-cpu";
  info.shard = {index, count};
  info.started = "2026-11-22T0" + std::to_string(index) + ":00:00Z";
  info.wall_s = index + 1.0;
  std::vector<ModelResult> results;
  for (const auto& id : ids) {
    ModelResult r;
    r.id = id;
    r.ok = id != "bad";
    if (!r.ok) r.reason = "cannot read mesh bad.obj";
    results.push_back(r);
  }
  return make_summary(info, results);
}

std::string merge_error(const std::vector<std::pair<std::string, nlohmann::json>>& named, bool partial = false) {
  try {
    merge_summaries(named, partial);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(BatchSummary, CountsAndNames) {
  const auto s = shard_summary(1, 3, {"z", "bad", "a"});
  EXPECT_EQ(s["format"], "splatcl-batch-summary");
  EXPECT_EQ(s["counts"]["models"], 3);
  EXPECT_EQ(s["counts"]["ok"], 2);
  EXPECT_EQ(s["counts"]["failed"], 1);
  EXPECT_EQ(s["counts"]["built"], 2);  // the ok ones that were not reused; the failed one is not "built"
  EXPECT_EQ(s["models"][0]["id"], "a");  // id order
  EXPECT_EQ(s["models"][1]["reason"], "cannot read mesh bad.obj");
  EXPECT_EQ(s["shard"]["indices"], nlohmann::json::array({1}));
  EXPECT_EQ(summary_name({0, 1}), "summary.json");
  EXPECT_EQ(summary_name({2, 8}), "summary-2-of-8.json");
}

TEST(BatchSummary, MergesCompleteShards) {
  const auto merged = merge_summaries({{"s1", shard_summary(1, 3, {"b", "e"})},
                                       {"s0", shard_summary(0, 3, {"a", "d"})},
                                       {"s2", shard_summary(2, 3, {"c"})}},
                                      false);
  EXPECT_EQ(merged["counts"]["models"], 5);
  EXPECT_EQ(merged["shard"]["indices"], nlohmann::json::array({0, 1, 2}));
  std::vector<std::string> ids;
  for (const auto& m : merged["models"]) ids.push_back(m["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"a", "b", "c", "d", "e"}));
  EXPECT_EQ(merged["started"], "2026-11-22T00:00:00Z");
  EXPECT_EQ(merged["wall_s"], 3.0);
  EXPECT_EQ(merged["merged_from"], nlohmann::json::array({"s1", "s0", "s2"}));
  // The runs' working directory is kept when every shard ran in one, else dropped (the relative
  // paths of the first would be taken for all).
  auto in_a = shard_summary(0, 2, {"a", "c", "e"}), in_b = shard_summary(1, 2, {"b", "d"});
  in_a["working_directory"] = in_b["working_directory"] = "/home/a";
  EXPECT_EQ(merge_summaries({{"a", in_a}, {"b", in_b}}, false)["working_directory"], "/home/a");
  in_b["working_directory"] = "/home/b";
  EXPECT_FALSE(merge_summaries({{"a", in_a}, {"b", in_b}}, false).contains("working_directory"));
  // A merged summary merges again like any other.
  EXPECT_EQ(merge_summaries({{"m", merged}}, false)["counts"]["models"], 5);
  // A failed model that says reused (an edited summary) is not counted as reused: built = ok −
  // reused wrapped round to 18446744073709551615.
  auto edited = shard_summary(0, 1, {"bad", "a"}, "c0ffee", 2);
  for (auto& m : edited["models"]) m["reused"] = true;
  const auto counts = merge_summaries({{"e", edited}}, false)["counts"];
  EXPECT_EQ(counts["reused"], 1);
  EXPECT_EQ(counts["built"], 0);
}

TEST(BatchSummary, MergeRefusesInconsistentInput) {
  const auto s0 = shard_summary(0, 2, {"a", "c", "e"});
  const auto s1 = shard_summary(1, 2, {"b", "d"});
  EXPECT_EQ(merge_error({{"s0", s0}}), "batch merge: missing shard 1/2 (pass --partial to merge anyway)");
  EXPECT_EQ(merge_summaries({{"s0", s0}}, true)["counts"]["models"], 3);
  EXPECT_EQ(merge_error({{"s0", s0}, {"again", s0}}), "again: shard 0/2 is also in s0");
  EXPECT_EQ(merge_error({{"s0", s0}, {"other", shard_summary(1, 2, {"b", "d"}, "beef")}}),
            "other: from a different run than s0: other models, inputs or parameters (manifest checksum beef vs c0ffee)");
  // The same manifest and parameters run on another device is refused too (it merged silently).
  auto elsewhere = shard_summary(1, 2, {"b", "d"});
  elsewhere["device"] = "reference";
  EXPECT_EQ(merge_error({{"s0", s0}, {"elsewhere", elsewhere}}), "elsewhere: ran on device 'reference', s0 on 'pthread-test-cpu'; rerun the shards on one device");
  EXPECT_EQ(merge_error({{"s0", s0}, {"three", shard_summary(1, 3, {"b"})}}), "three: split into 3 shards, s0 into 2");
  EXPECT_EQ(merge_error({{"s0", s0}, {"dup", shard_summary(1, 2, {"b", "c"})}}), "dup: model 'c' is also in s0");
  EXPECT_EQ(merge_error({{"s0", s0}, {"short", shard_summary(1, 2, {"b"})}}), "batch merge: the shards hold 4 models, the manifest 5");
  EXPECT_EQ(merge_error({}), "batch merge: no summaries given");
  EXPECT_EQ(failed_models(merge_summaries({{"s0", s0}, {"s1", shard_summary(1, 2, {"bad", "d"})}}, false)), 1u);
  EXPECT_NO_THROW(merge_summaries({{"s0", s0}, {"s1", s1}}, false));
}

// A summary file with a key splatcl does not write is refused on reading (merge copied the first
// summary's unknown keys into its output); its own summaries, plain and merged, are read.
TEST(BatchSummary, ReadingRefusesUnknownKeys) {
  const std::string path = (std::filesystem::temp_directory_path() / "splatcl-summary-keys.json").string();
  const auto write = [&](const nlohmann::json& doc) { std::ofstream(path) << doc.dump(); };
  const auto s0 = shard_summary(0, 2, {"a", "c", "e"});
  write(s0);
  EXPECT_NO_THROW(read_summary(path));
  write(merge_summaries({{"s0", s0}, {"s1", shard_summary(1, 2, {"b", "d"})}}, false));
  EXPECT_NO_THROW(read_summary(path));
  // The paths merge checks -o against: strings, the working directory absolute.
  for (const auto& [key, value, expected] : std::vector<std::tuple<std::string, nlohmann::json, std::string>>{
           {"working_directory", 5, "'working_directory' is not a string"},
           {"output_dir", nlohmann::json::array(), "'output_dir' is not a string"},
           {"working_directory", "relative/dir", "'working_directory' is not an absolute path"}}) {
    auto doc = s0;
    doc[key] = value;
    write(doc);
    try {
      read_summary(path);
      ADD_FAILURE() << "accepted " << key << " = " << value.dump();
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), path + ": " + expected);
    }
  }
  auto typo = s0;
  typo["wall_seconds"] = 3;
  write(typo);
  try {
    read_summary(path);
    ADD_FAILURE() << "accepted an unknown key";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": unknown key 'wall_seconds' in the summary (known: format, version"), std::string::npos) << e.what();
  }
  // Inside a model's entry and its outputs too (merge copies the entries as they are).
  auto with_outputs = s0;
  ModelResult built;
  built.id = "f";
  built.ok = false, built.reason = "out of memory", built.warning = "far from the origin";
  built.outputs.push_back({});
  built.outputs.back().kind = "splats";
  with_outputs["models"].push_back(to_json(built));
  write(with_outputs);
  EXPECT_NO_THROW(read_summary(path));  // every key to_json writes
  for (const auto& [pointer, expected] : std::vector<std::pair<std::string, std::string>>{
           {"/models/1/input_sha", "unknown key 'input_sha' in models[1] (known: id, input"},
           {"/models/3/outputs/splats/build_seconds", "unknown key 'build_seconds' in models[3].outputs.splats (known: reused"}}) {
    auto doc = with_outputs;
    doc[nlohmann::json::json_pointer(pointer)] = 1;
    write(doc);
    try {
      read_summary(path);
      ADD_FAILURE() << "accepted " << pointer;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": " + expected), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace splatcl::batch
