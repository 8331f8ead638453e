#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>

#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl {
namespace {

TEST(Runtime, ListsAtLeastOneDeviceWithSaneProperties) {
  const auto devices = list_devices();
  ASSERT_FALSE(devices.empty());
  for (const auto& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.compute_units, 0u);
    EXPECT_GT(d.global_mem_bytes, 0u);
    EXPECT_GT(d.max_work_group_size, 0u);
  }
}

TEST(Runtime, ChoosesByIndexTypeAndName) {
  const auto devices = list_devices();
  EXPECT_EQ(choose_device("0").index, 0u);
  const auto& first = devices.front();
  EXPECT_EQ(choose_device(first.type).type, first.type);
  EXPECT_EQ(choose_device(first.name.substr(0, 4)).index, first.index);
}

TEST(Runtime, UnknownSelectorIsAClearError) {
  EXPECT_THROW(choose_device("no-such-device-xyz"), Error);
  EXPECT_THROW(choose_device("999"), Error);
}

TEST(Runtime, EnvironmentVariableChoosesWhenNoSelector) {
  ::setenv(kDeviceEnvVar, "no-such-device-xyz", 1);
  EXPECT_THROW(choose_device(""), Error);
  ::setenv(kDeviceEnvVar, "0", 1);
  EXPECT_EQ(choose_device("").index, 0u);
  ::unsetenv(kDeviceEnvVar);
}

TEST(Runtime, ExpandsIncludesWithLineMarkers) {
  const std::string source = expand_kernel_source("common.h");
  EXPECT_NE(source.find("#line 1 \"common.h\""), std::string::npos);
  EXPECT_THROW(expand_kernel_source("missing.cl"), Error);
}

TEST(Runtime, BuildFailureNamesFileAndLine) {
  auto runtime = Runtime::create();
  try {
    runtime->program("common.h", "-DSPLATCL_FORCE_BUILD_ERROR");
    FAIL() << "expected a build error";
  } catch (const Error& e) {
    const std::string message = e.what();
    // The device's build log names the original file and line ("common.h:12:1: ..."), thanks to #line.
    const auto at = message.find("common.h:");
    ASSERT_NE(at, std::string::npos) << message;
    EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(message[at + 9]))) << message;
    EXPECT_NE(message.find("failed"), std::string::npos) << message;
  }
}

TEST(Runtime, CachesProgramsPerFileAndOptions) {
  auto runtime = Runtime::create();
  auto a = runtime->program("common.h");
  auto b = runtime->program("common.h");
  EXPECT_EQ(a(), b());
}

}  // namespace
}  // namespace splatcl
