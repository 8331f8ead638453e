#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <tuple>
#include <vector>

#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"
#include "primitives_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives::testing {
namespace {

std::vector<std::uint32_t> expected_scan(const std::vector<std::uint32_t>& in, ScanKind kind) {
  std::vector<std::uint32_t> out(in.size());
  if (kind == ScanKind::Exclusive) {
    std::exclusive_scan(in.begin(), in.end(), out.begin(), std::uint32_t{0});
  } else {
    std::inclusive_scan(in.begin(), in.end(), out.begin());
  }
  return out;
}

// Through the host-vector entry points, which scan in place (in and out the same buffer).
std::vector<std::uint32_t> run_scan(Impl impl, const std::vector<std::uint32_t>& in, ScanKind kind) {
  if (impl == Impl::Reference) return reference::scan(in, kind);
  return scan(runtime(), in, kind, shape_of(impl));
}

class ScanTest : public ::testing::TestWithParam<std::tuple<Impl, std::size_t>> {};

TEST_P(ScanTest, MatchesStdScansOnRandomAndWrappingInputs) {
  const auto [impl, n] = GetParam();
  // Full-range values wrap the sums constantly; all-maximum values wrap at every element; small
  // values keep the sums exact.
  const std::vector<std::vector<std::uint32_t>> inputs = {
      random_values<std::uint32_t>(n, 0xFFFFFFFFu, 1), std::vector<std::uint32_t>(n, 0xFFFFFFFFu),
      random_values<std::uint32_t>(n, 3, 2)};
  for (std::size_t input = 0; input < inputs.size(); ++input) {
    for (const ScanKind kind : {ScanKind::Exclusive, ScanKind::Inclusive}) {
      SCOPED_TRACE("input " + std::to_string(input) + (kind == ScanKind::Exclusive ? " exclusive" : " inclusive"));
      EXPECT_EQ(run_scan(impl, inputs[input], kind), expected_scan(inputs[input], kind));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllImplsAndSizes, ScanTest, ::testing::Combine(::testing::ValuesIn(kImpls),
                                                                        ::testing::ValuesIn(kSizes)),
                         impl_size_name);

class ScannerTest : public ::testing::TestWithParam<Shape> {};

TEST_P(ScannerTest, OutOfPlaceKeepsInputAndReportsTotal) {
  Runtime& rt = runtime();
  Scanner scanner(rt, GetParam());
  EXPECT_EQ(scanner.shape(), GetParam());
  const auto in = random_values<std::uint32_t>(300001, 0xFFFFFFFFu, 3);
  const std::size_t bytes = in.size() * sizeof(std::uint32_t);
  cl::Buffer in_buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test input");
  cl::Buffer out_buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test output");
  rt.queue().enqueueWriteBuffer(in_buffer, CL_TRUE, 0, bytes, in.data());
  const std::uint32_t expected_total = std::accumulate(in.begin(), in.end(), std::uint32_t{0});

  Profiler profiler;
  EXPECT_EQ(scanner.run(in_buffer, out_buffer, in.size(), ScanKind::Exclusive, true, &profiler), expected_total);
  EXPECT_FALSE(profiler.entries().empty());
  std::vector<std::uint32_t> out(in.size()), in_after(in.size());
  rt.queue().enqueueReadBuffer(out_buffer, CL_TRUE, 0, bytes, out.data());
  rt.queue().enqueueReadBuffer(in_buffer, CL_TRUE, 0, bytes, in_after.data());
  EXPECT_EQ(out, expected_scan(in, ScanKind::Exclusive));
  EXPECT_EQ(in_after, in);

  // Without read_total the result is 0, and the total is left on the device.
  EXPECT_EQ(scanner.run(in_buffer, out_buffer, in.size(), ScanKind::Inclusive, false), 0u);
  std::uint32_t device_total = 0;
  rt.queue().enqueueReadBuffer(scanner.total_buffer(), CL_TRUE, 0, sizeof(device_total), &device_total);
  EXPECT_EQ(device_total, expected_total);
  rt.queue().enqueueReadBuffer(out_buffer, CL_TRUE, 0, bytes, out.data());
  EXPECT_EQ(out, expected_scan(in, ScanKind::Inclusive));

  // An empty scan has a total of 0, on the host and on the device.
  EXPECT_EQ(scanner.run(in_buffer, out_buffer, 0, ScanKind::Exclusive), 0u);
  rt.queue().enqueueReadBuffer(scanner.total_buffer(), CL_TRUE, 0, sizeof(device_total), &device_total);
  EXPECT_EQ(device_total, 0u);
}

TEST_P(ScannerTest, ReusesScratchAcrossSizes) {
  Runtime& rt = runtime();
  Scanner scanner(rt, GetParam());
  for (const std::size_t n : {std::size_t{5000}, std::size_t{700000}, std::size_t{3}, std::size_t{700000}}) {
    const auto in = random_values<std::uint32_t>(n, 0xFFFF, n);
    const std::size_t bytes = n * sizeof(std::uint32_t);
    cl::Buffer buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test values");
    rt.queue().enqueueWriteBuffer(buffer, CL_TRUE, 0, bytes, in.data());
    scanner.run(buffer, buffer, n, ScanKind::Exclusive, false);
    std::vector<std::uint32_t> out(n);
    rt.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, bytes, out.data());
    EXPECT_EQ(out, expected_scan(in, ScanKind::Exclusive)) << n;
  }
}

TEST_P(ScannerTest, UndersizedBufferIsAnError) {
  Runtime& rt = runtime();
  Scanner scanner(rt, GetParam());
  cl::Buffer small = rt.buffer(CL_MEM_READ_WRITE, 64, "small");
  EXPECT_THROW(scanner.run(small, small, 1000, ScanKind::Exclusive), Error);
}

INSTANTIATE_TEST_SUITE_P(BothShapes, ScannerTest, ::testing::Values(Shape::Cpu, Shape::Gpu), shape_name);

TEST(ReferenceScan, AnyThreadCountAndInPlace) {
  const auto in = random_values<std::uint32_t>(500009, 0xFFFFFFFFu, 4);
  for (const unsigned threads : {1u, 3u, 8u}) {
    for (const ScanKind kind : {ScanKind::Exclusive, ScanKind::Inclusive}) {
      std::vector<std::uint32_t> values = in;
      const std::uint32_t total = reference::scan(values, values, kind, threads);
      EXPECT_EQ(values, expected_scan(in, kind)) << threads;
      EXPECT_EQ(total, std::accumulate(in.begin(), in.end(), std::uint32_t{0}));
    }
  }
  std::vector<std::uint32_t> too_short(3);
  EXPECT_THROW(reference::scan(in, too_short, ScanKind::Exclusive), Error);
}

}  // namespace
}  // namespace splatcl::primitives::testing
