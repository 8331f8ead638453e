#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
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
  // By name: a device whose full name no other device's name, and no platform's name or vendor,
  // contains (two GPUs of one model, or Intel's CPU and GPU runtimes, share their prefixes).
  const auto lower = [](std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
  };
  for (const DeviceInfo& d : devices) {
    const std::string name = lower(d.name);
    const bool unique = std::none_of(devices.begin(), devices.end(), [&](const DeviceInfo& other) {
      return lower(other.platform).find(name) != std::string::npos || lower(other.platform_vendor).find(name) != std::string::npos ||
             (other.index != d.index && lower(other.name).find(name) != std::string::npos);
    });
    if (unique) {
      EXPECT_EQ(choose_device(d.name).index, d.index) << d.name;
    }
  }
}

// PoCL on an Intel CPU names Intel in its device name: 'intel' is Intel's runtime by its platform,
// 'pocl' PoCL by its platform's vendor, and a substring of both device names is refused.
TEST(Runtime, NameSelectorsPreferPlatformsAndRefuseAmbiguity) {
  const auto device = [](std::size_t index, const char* platform, const char* platform_vendor, const char* name) {
    DeviceInfo d;
    d.index = index, d.platform = platform, d.platform_vendor = platform_vendor, d.name = name, d.type = "cpu";
    return d;
  };
  const std::vector<DeviceInfo> devices{
      device(0, "Portable Computing Language", "The pocl project", "pthread-skylake-avx512-Intel(R) Xeon(R) Processor"),
      device(1, "Intel(R) OpenCL", "Intel(R) Corporation", "Intel(R) Xeon(R) Processor")};
  EXPECT_EQ(match_device(devices, "intel").index, 1u);
  EXPECT_EQ(match_device(devices, "Intel(R) OpenCL").index, 1u);
  EXPECT_EQ(match_device(devices, "pocl").index, 0u);
  EXPECT_EQ(match_device(devices, "pthread").index, 0u);
  try {
    match_device(devices, "xeon");
    ADD_FAILURE() << "an ambiguous selector was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'xeon' matches 2 OpenCL devices by device name: [0] Portable"), std::string::npos) << e.what();
  }
  EXPECT_THROW(match_device(devices, "cpu-less"), Error);
}

// Sets (or with nullptr unsets) $SPLATCL_DEVICE for one scope: the rest of the process keeps the
// device it was started with (tests/devices/on_devices.sh reruns these tests on each device).
class ScopedDeviceVariable {
 public:
  explicit ScopedDeviceVariable(const char* value) {
    if (const char* old = std::getenv(kDeviceEnvVar)) saved_ = old;
    value ? ::setenv(kDeviceEnvVar, value, 1) : ::unsetenv(kDeviceEnvVar);
  }
  ~ScopedDeviceVariable() { saved_.empty() ? ::unsetenv(kDeviceEnvVar) : ::setenv(kDeviceEnvVar, saved_.c_str(), 1); }
  ScopedDeviceVariable(const ScopedDeviceVariable&) = delete;
  ScopedDeviceVariable& operator=(const ScopedDeviceVariable&) = delete;

 private:
  std::string saved_;
};

TEST(Runtime, SimulatorsAreNeverTheDefault) {
  const auto all = list_devices();
  for (const auto& d : default_devices()) EXPECT_NE(d.type, "simulator") << d.name;
  const DeviceInfo chosen = [] {
    ScopedDeviceVariable unset(nullptr);
    return choose_device();
  }();
  EXPECT_NE(chosen.type, "simulator") << chosen.name;
  const bool pocl = std::any_of(all.begin(), all.end(), [](const DeviceInfo& d) { return d.platform.find("Portable Computing") == 0; });
  const bool gpu = std::any_of(all.begin(), all.end(), [](const DeviceInfo& d) { return d.type == "gpu"; });
  if (pocl && !gpu) {
    EXPECT_EQ(chosen.platform.find("Portable Computing"), 0u) << "PoCL stays the default CPU device";
  }
  const auto simulator = std::find_if(all.begin(), all.end(), [](const DeviceInfo& d) { return d.type == "simulator"; });
  if (simulator == all.end()) GTEST_SKIP() << "no simulator (Oclgrind) registered: scripts/setup.sh writes .opencl/env";
  EXPECT_EQ(choose_device("simulator").index, simulator->index);  // named, it is chosen
  EXPECT_EQ(choose_device("oclgrind").index, simulator->index);
  if (!gpu) {
    EXPECT_THROW(choose_device("gpu"), Error);  // Oclgrind's GPU bit does not make it a GPU
  }
}

TEST(Runtime, UnknownSelectorIsAClearError) {
  EXPECT_THROW(choose_device("no-such-device-xyz"), Error);
  EXPECT_THROW(choose_device("999"), Error);
}

TEST(Runtime, EnvironmentVariableChoosesWhenNoSelector) {
  {
    ScopedDeviceVariable missing("no-such-device-xyz");
    EXPECT_THROW(choose_device(""), Error);
  }
  ScopedDeviceVariable first("0");
  EXPECT_EQ(choose_device("").index, 0u);
}

TEST(Runtime, ExpandsIncludesWithLineMarkers) {
  const std::string source = expand_kernel_source("common.h");
  EXPECT_NE(source.find("#line 1 \"common.h\""), std::string::npos);
  EXPECT_THROW(expand_kernel_source("missing.cl"), Error);
}

// Whether `text` holds a location "name.h:LINE" or "name.cl:LINE".
bool names_source_line(const std::string& text) {
  for (const char* extension : {".h:", ".cl:"}) {
    for (std::size_t at = text.find(extension); at != std::string::npos; at = text.find(extension, at + 1)) {
      const std::size_t digit = at + std::char_traits<char>::length(extension);
      const bool named = at > 0 && (std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_');
      if (named && digit < text.size() && std::isdigit(static_cast<unsigned char>(text[digit]))) return true;
    }
  }
  return false;
}

TEST(Runtime, BuildFailureNamesFileAndLine) {
  // The log formats of PoCL and Intel (#line honoured), and of Oclgrind (its own input name).
  EXPECT_TRUE(names_source_line("common.h:12:1: error: forced"));
  EXPECT_TRUE(names_source_line("input.cl:13:1: error: forced"));
  EXPECT_FALSE(names_source_line("error: forced, in common.h: somewhere"));
  auto runtime = Runtime::create();
  try {
    runtime->program("common.h", "-DSPLATCL_FORCE_BUILD_ERROR");
    FAIL() << "expected a build error";
  } catch (const Error& e) {
    const std::string message = e.what();
    // The message names the file; the device's build log follows with a "file:line" location.
    // PoCL and Intel honour #line ("common.h:12:1: ..."); Oclgrind names its own input
    // ("input.cl:13:1: ..."), so any source file name is accepted before the line number.
    EXPECT_NE(message.find("kernel build of common.h failed on '" + runtime->info().name + "'"), std::string::npos)
        << message;
    EXPECT_TRUE(names_source_line(message)) << message;
    // One line (the CLI's error contract: the whole log with its newlines printed as one line of
    // "\n"s); the whole log is in the file it names.
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    const std::size_t at = message.find("; the whole log: ");
    ASSERT_NE(at, std::string::npos) << message;
    const std::string path = message.substr(at + std::char_traits<char>::length("; the whole log: "));
    std::ifstream log(path);
    const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    EXPECT_TRUE(names_source_line(text)) << path;
    std::filesystem::remove(path);
  }
}

// A work-group the device cannot take is refused at launch with what the kernel allows there.
TEST(Runtime, OversizedWorkGroupNamesTheLimits) {
  auto runtime = Runtime::create();
  cl::Program program(runtime->context(), "__kernel void probe(__global int* a) { a[get_global_id(0)] = 1; }");
  program.build({runtime->device()});
  cl::Kernel kernel(program, "probe");
  cl::Buffer buffer = runtime->buffer(CL_MEM_READ_WRITE, 4 * sizeof(int), "probe output");
  set_args(kernel, buffer);
  const std::size_t too_many = runtime->info().max_work_group_size * 2;
  try {
    enqueue_1d(runtime->queue(), kernel, too_many, too_many, nullptr, "probe");
    runtime->queue().finish();
    FAIL() << "a work-group of " << too_many << " work-items was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("launching kernel probe with " + std::to_string(too_many) + " work-items per group"),
              std::string::npos) << message;
    EXPECT_NE(message.find("B local memory on '" + runtime->info().name + "'"), std::string::npos) << message;
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
