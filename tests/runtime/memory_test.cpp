// The memory guard (io/memory.hpp): $SPLATCL_MEMORY_LIMIT's syntax, and that a need beyond the
// room is refused with the figures while one within it passes.
#include <gtest/gtest.h>

#include <cstdlib>
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

}  // namespace
}  // namespace splatcl
