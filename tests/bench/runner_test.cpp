// Orchestration of a bench run: scaling names, the arguments a thread-scaling child gets, devices.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

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

// This process's own arguments, as the kernel recorded them (the gtest flags ctest passes, or
// none), without the program name: what a thread-scaling child is started with.
TEST(BenchRunner, OwnArgumentsComeFromProcCmdline) {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  const std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t program_end = cmdline.find('\0');
  ASSERT_NE(program_end, std::string::npos);
  EXPECT_NE(cmdline.substr(0, program_end).find("splatcl_tests_bench"), std::string::npos);
  std::string expected;
  for (const std::string& a : own_arguments()) {
    EXPECT_EQ(a.find("splatcl_tests_bench"), std::string::npos) << a;
    expected += a + '\0';
  }
  EXPECT_EQ(expected, cmdline.substr(program_end + 1));
}

TEST(BenchRunner, DevicesAreChosenOnceEach) {
  const auto all = bench_devices({});
  ASSERT_FALSE(all.empty());
  const auto twice = bench_devices({"0", "0"});
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_EQ(twice[0].index, 0u);
  EXPECT_THROW(bench_devices({"no-such-device-name"}), Error);
  // "all": every device but simulators, as with no selector; a device named beside it is not repeated.
  const auto named_all = bench_devices({"all"});
  ASSERT_EQ(named_all.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(named_all[i].index, all[i].index);
  EXPECT_EQ(bench_devices({"all", std::to_string(all[0].index)}).size(), all.size());
  for (const auto& device : named_all) EXPECT_NE(device.type, "simulator");
}

}  // namespace
}  // namespace splatcl::bench
