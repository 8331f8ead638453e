#pragma once
// One Runtime per test process, shared by the kernel tests of every stage. The device is the
// default choice, or the one $SPLATCL_DEVICE names: tests/CMakeLists.txt reruns the kernel tests
// with it set to each device present (tests/devices/on_devices.sh).
//
// The runtime is released by a GoogleTest environment when RUN_ALL_TESTS ends, while the OpenCL
// implementation is still loaded. A function-static shared_ptr would be released among the static
// destructors at exit, after those of the implementation's LLVM, and abort the process there
// (Oclgrind: "corrupted double-linked list", exit 134).
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "runtime/runtime.hpp"

namespace splatcl::testing {

inline std::shared_ptr<Runtime>& shared_runtime_slot() {
  static std::shared_ptr<Runtime> slot;
  return slot;
}

class ReleaseSharedRuntime : public ::testing::Environment {
 public:
  void TearDown() override { shared_runtime_slot().reset(); }
};

// Registered before main: gtest owns the environment and runs its TearDown after the last test.
inline ::testing::Environment* const kReleaseSharedRuntime =
    ::testing::AddGlobalTestEnvironment(new ReleaseSharedRuntime);

inline Runtime& shared_runtime() {
  auto& slot = shared_runtime_slot();
  if (!slot) {
    slot = Runtime::create();
    std::fprintf(stderr, "[ device   ] %s / %s (%s)\n", slot->info().platform.c_str(), slot->info().name.c_str(),
                 slot->info().type.c_str());
  }
  return *slot;
}

}  // namespace splatcl::testing
