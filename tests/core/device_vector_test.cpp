// DeviceVector: size and capacity (the storage grows only past the largest size asked for, and is
// kept, contents and all, for smaller sizes), uploads and reads that round-trip exactly, and the
// byte check of caller-owned buffers.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "core/device_vector.hpp"
#include "runtime/error.hpp"
#include "runtime/test_runtime.hpp"

namespace splatcl {
namespace {

TEST(DeviceVector, StartsEmptyAndAlwaysHoldsAtLeastOneElement) {
  DeviceVector<float> v(testing::shared_runtime(), "test values");
  EXPECT_EQ(v.size(), 0u);
  EXPECT_EQ(v.capacity(), 0u);
  EXPECT_FALSE(v.buffer()());
  v.resize(0);  // OpenCL has no zero-sized buffers: a kernel argument must still be valid
  EXPECT_TRUE(v.buffer()());
  EXPECT_EQ(v.size(), 0u);
  EXPECT_EQ(v.capacity(), 1u);
  EXPECT_GE(buffer_bytes(v.buffer()), sizeof(float));  // an implementation may round a tiny buffer up
  EXPECT_TRUE(v.read().empty());
}

TEST(DeviceVector, GrowsOnlyPastItsCapacityAndKeepsTheStorageForSmallerSizes) {
  Runtime& runtime = testing::shared_runtime();
  DeviceVector<std::uint32_t> v(runtime, "test keys");
  std::vector<std::uint32_t> values(1000);
  std::iota(values.begin(), values.end(), 7u);
  v.assign(values);
  EXPECT_EQ(v.size(), 1000u);
  EXPECT_EQ(v.capacity(), 1000u);
  EXPECT_EQ(v.bytes(), 4000u);
  EXPECT_EQ(v.read(), values);
  const cl_mem storage = v.buffer()();

  // Smaller: same storage, and its first elements are untouched.
  v.resize(10);
  EXPECT_EQ(v.buffer()(), storage);
  EXPECT_EQ(v.capacity(), 1000u);
  EXPECT_EQ(v.read(), std::vector<std::uint32_t>(values.begin(), values.begin() + 10));
  v.resize(1000);
  EXPECT_EQ(v.buffer()(), storage);
  EXPECT_EQ(v.read(5), std::vector<std::uint32_t>(values.begin(), values.begin() + 5));

  // Larger: new storage of exactly the size asked for.
  v.resize(1001);
  EXPECT_NE(v.buffer()(), storage);
  EXPECT_EQ(v.capacity(), 1001u);
  EXPECT_EQ(buffer_bytes(v.buffer()), 1001u * sizeof(std::uint32_t));

  // A non-blocking upload is in place once a later blocking command has run.
  const std::vector<std::uint32_t> next(300, 42u);
  v.assign(next, false);
  EXPECT_EQ(v.size(), 300u);
  EXPECT_EQ(v.read(), next);
  // read(n) never reads past the size.
  EXPECT_EQ(v.read(100000).size(), 300u);
}

TEST(DeviceVector, RequireBytesNamesTheBufferAndTheShortfall) {
  DeviceVector<float> v(testing::shared_runtime(), "test values");
  v.resize(4);
  EXPECT_NO_THROW(require_bytes(v.buffer(), 16, "input"));
  try {
    require_bytes(v.buffer(), 17, "CSM capture z1");
    FAIL() << "no error for a buffer 1 byte short";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "CSM capture z1: buffer holds 16 bytes, 17 needed");
  }
  EXPECT_THROW(require_bytes(cl::Buffer(), 1, "never allocated"), Error);
  EXPECT_EQ(buffer_bytes(cl::Buffer()), 0u);
}

}  // namespace
}  // namespace splatcl
