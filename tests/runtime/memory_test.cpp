// The memory guard (io/memory.hpp): $SPLATCL_MEMORY_LIMIT's syntax, and that a need beyond the
// room is refused with the figures while one within it passes.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/memory.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

// Sets $SPLATCL_MEMORY_LIMIT for one scope.
class ScopedLimit {
 public:
  explicit ScopedLimit(const char* value) {
    if (const char* old = std::getenv("SPLATCL_MEMORY_LIMIT")) old_ = old, had_ = true;
    ::setenv("SPLATCL_MEMORY_LIMIT", value, 1);
  }
  ~ScopedLimit() { had_ ? ::setenv("SPLATCL_MEMORY_LIMIT", old_.c_str(), 1) : ::unsetenv("SPLATCL_MEMORY_LIMIT"); }

 private:
  std::string old_;
  bool had_ = false;
};

std::string error_of(std::uint64_t bytes) {
  try {
    require_memory(bytes, "the test", "ask for less");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MemoryGuard, LimitTakesBytesOrABinarySuffix) {
  const std::pair<const char*, std::uint64_t> cases[] = {{"0", 0}, {"4096", 4096}, {"3k", 3072}, {"512M", 512ull << 20}, {"2G", 2ull << 30}, {"1T", 1ull << 40}};
  for (const auto& [text, bytes] : cases) {
    const ScopedLimit limit(text);
    EXPECT_EQ(memory_limit_from_environment(), bytes) << text;
  }
  for (const char* bad : {"lots", "1.5G", "-1", "2GB", "G", "1e9", "9999999999999", "999999999999T", "16777216T"}) {
    const ScopedLimit limit(bad);
    EXPECT_THROW(memory_limit_from_environment(), Error) << bad;
  }
  const ScopedLimit empty("");
  EXPECT_FALSE(memory_limit_from_environment());
}

TEST(MemoryGuard, SizesAreWrittenInTheirUnit) {
  EXPECT_EQ(memory_size(512), "512 bytes");
  EXPECT_EQ(memory_size(12 * 1024 + 100), "12 KiB");
  EXPECT_EQ(memory_size(340ull << 20), "340 MiB");
  EXPECT_EQ(memory_size((5ull << 30) / 4), "1.25 GiB");
}

TEST(MemoryGuard, ANeedBeyondTheRoomIsRefusedWithItsFigures) {
  {
    // The limit counts what the process holds (its resident set, far above 1 MiB with a test binary).
    const ScopedLimit limit("1M");
    EXPECT_EQ(available_memory(), 0u);
    EXPECT_EQ(error_of(1ull << 30), "the test needs about 1.00 GiB more memory, and 0 bytes is available within SPLATCL_MEMORY_LIMIT: ask for less");
  }
  const ScopedLimit limit("1T");
  const auto room = available_memory();
  ASSERT_TRUE(room) << "this machine's /proc/meminfo has MemAvailable";
  EXPECT_GT(*room, 1ull << 20);
  EXPECT_EQ(error_of(1ull << 20), "");
  EXPECT_NE(error_of(*room + (1ull << 30)).find("more memory, and"), std::string::npos);
}

// The process's own cgroups, as /proc/self/cgroup names them, under a made-up mount: a Slurm job's
// limit lies in a sub-folder (the mount's root has none), the kernel reclaims inactive page cache
// before it kills, and a folder not visible (a cgroup namespace) is read at the root.
TEST(MemoryGuard, CgroupRoomIsTheOwnCgroupsLimitLessWhatCannotBeReclaimed) {
  const std::filesystem::path mount = std::filesystem::temp_directory_path() / fmt::format("splatcl_cgroup_{}", ::getpid());
  std::filesystem::remove_all(mount);
  const auto put = [&](const std::filesystem::path& file, const std::string& text) {
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
  };
  // v2: the job's folder sets 1000 with 800 in use, 300 of it inactive cache; its step has no limit;
  // the root has no memory.max at all.
  put(mount / "job/memory.max", "1000\n");
  put(mount / "job/memory.current", "800\n");
  put(mount / "job/memory.stat", "anon 400\nfile 400\ninactive_file 300\nactive_file 100\n");
  put(mount / "job/step/memory.max", "max\n");
  put(mount / "job/step/memory.current", "700\n");
  EXPECT_EQ(cgroup_memory_room("0::/job/step\n", mount.string()), 500u);
  EXPECT_EQ(cgroup_memory_room("0::/\n", mount.string()), std::nullopt);
  // A tighter parent wins; usage beyond the limit leaves 0.
  put(mount / "job/step/memory.max", "450\n");
  EXPECT_EQ(cgroup_memory_room("0::/job/step\n", mount.string()), 0u);
  // v1: the memory controller's line; the hierarchical limit (from a parent) below the folder's own.
  put(mount / "memory/slurm/job/memory.limit_in_bytes", "9223372036854771712\n");
  put(mount / "memory/slurm/job/memory.usage_in_bytes", "1500\n");
  put(mount / "memory/slurm/job/memory.stat", "cache 1100\nhierarchical_memory_limit 1800\ntotal_inactive_file 1000\n");
  EXPECT_EQ(cgroup_memory_room("5:cpu,cpuacct:/slurm/job\n4:memory:/slurm/job\n", mount.string()), 1300u);
  // Not visible under the mount (its own namespace): the root's files, here none.
  EXPECT_EQ(cgroup_memory_room("4:memory:/elsewhere\n", mount.string()), std::nullopt);
  std::filesystem::remove_all(mount);
}

}  // namespace
}  // namespace splatcl
