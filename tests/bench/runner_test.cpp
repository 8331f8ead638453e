// Orchestration of a bench run: scaling names, the arguments a thread-scaling child gets, devices.
#include <gtest/gtest.h>

#include "bench/runner.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

TEST(BenchRunner, ParsesScaling) {
  EXPECT_EQ(parse_scaling("none"), Scaling::None);
  EXPECT_EQ(parse_scaling("size"), Scaling::Size);
  EXPECT_EQ(parse_scaling("threads"), Scaling::Threads);
  EXPECT_THROW(parse_scaling("cores"), Error);
}

TEST(BenchRunner, ChildArgumentsDropTheOptionsTheParentHandles) {
  const std::vector<std::string> args{"bench", "csm",     "--scaling", "threads", "--json=out.json", "--quick", "--csv",
                                      "a.csv", "--runs",  "3",         "--compare", "base.json",     "--threshold", "5",
                                      "--plot", "plots",  "--device",  "0"};
  const std::vector<std::string> expected{"bench", "csm", "--quick", "--runs", "3", "--device", "0"};
  EXPECT_EQ(child_arguments(args), expected);
}

TEST(BenchRunner, OwnArgumentsComeFromProcCmdline) {
  // The test program itself: no arguments beyond gtest's own, and never the program name.
  for (const auto& a : own_arguments()) EXPECT_EQ(a.find("splatcl_tests_bench"), std::string::npos) << a;
}

TEST(BenchRunner, DevicesAreChosenOnceEach) {
  const auto all = bench_devices({});
  ASSERT_FALSE(all.empty());
  const auto twice = bench_devices({"0", "0"});
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_EQ(twice[0].index, 0u);
  EXPECT_THROW(bench_devices({"no-such-device-name"}), Error);
}

}  // namespace
}  // namespace splatcl::bench
