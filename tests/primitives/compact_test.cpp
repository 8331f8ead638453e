#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string>
#include <tuple>
#include <vector>

#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"
#include "primitives_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives::testing {
namespace {

std::vector<std::uint32_t> expected_keep(const std::vector<std::uint32_t>& values,
                                         const std::vector<std::uint32_t>& flags) {
  std::vector<std::uint32_t> kept;
  auto flag = flags.begin();
  std::copy_if(values.begin(), values.end(), std::back_inserter(kept), [&](std::uint32_t) { return *flag++ != 0; });
  return kept;
}

std::vector<std::uint32_t> expected_unique(std::vector<std::uint32_t> values) {
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

std::vector<std::uint32_t> run_keep(Impl impl, const std::vector<std::uint32_t>& values,
                                    const std::vector<std::uint32_t>& flags) {
  if (impl == Impl::Reference) return reference::keep_flagged(values, flags);
  return keep_flagged(runtime(), values, flags, shape_of(impl));
}

std::vector<std::uint32_t> run_unique(Impl impl, const std::vector<std::uint32_t>& values) {
  if (impl == Impl::Reference) return reference::unique(values);
  return unique(runtime(), values, shape_of(impl));
}

class CompactTest : public ::testing::TestWithParam<std::tuple<Impl, std::size_t>> {};

TEST_P(CompactTest, KeepFlaggedMatchesCopyIf) {
  const auto [impl, n] = GetParam();
  const auto values = random_values<std::uint32_t>(n, 0xFFFFFFFFu, 11);
  // Any non-zero flag keeps (a third of them, sparse, dense); none; all; alternating.
  const auto raw = random_values<std::uint32_t>(n, 0xFFFFFFFFu, 12);
  std::vector<std::vector<std::uint32_t>> flag_sets(6, std::vector<std::uint32_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    flag_sets[0][i] = raw[i] % 3 == 0 ? raw[i] : 0;
    flag_sets[1][i] = raw[i] % 1000 == 0;
    flag_sets[2][i] = raw[i] % 1000 != 0;
    flag_sets[3][i] = 0;
    flag_sets[4][i] = 0xFFFFFFFFu;
    flag_sets[5][i] = i % 2;
  }
  for (std::size_t set = 0; set < flag_sets.size(); ++set) {
    SCOPED_TRACE("flag set " + std::to_string(set));
    EXPECT_EQ(run_keep(impl, values, flag_sets[set]), expected_keep(values, flag_sets[set]));
  }
}

TEST_P(CompactTest, UniqueMatchesStdUnique) {
  const auto [impl, n] = GetParam();
  // Runs from a small alphabet, all equal, strictly increasing, runs of varying length, alternating
  // between 0 and the maximum (which a complement trick could confuse).
  std::vector<std::vector<std::uint32_t>> inputs = {random_values<std::uint32_t>(n, 3, 13),
                                                    std::vector<std::uint32_t>(n, 0xFFFFFFFFu),
                                                    std::vector<std::uint32_t>(n), std::vector<std::uint32_t>(n),
                                                    std::vector<std::uint32_t>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    inputs[2][i] = static_cast<std::uint32_t>(i);
    inputs[3][i] = static_cast<std::uint32_t>(i / (1 + i % 97));
    inputs[4][i] = i % 2 ? 0xFFFFFFFFu : 0u;
  }
  for (std::size_t input = 0; input < inputs.size(); ++input) {
    SCOPED_TRACE("input " + std::to_string(input));
    EXPECT_EQ(run_unique(impl, inputs[input]), expected_unique(inputs[input]));
  }
}

INSTANTIATE_TEST_SUITE_P(AllImplsAndSizes, CompactTest,
                         ::testing::Combine(::testing::ValuesIn(kImpls), ::testing::ValuesIn(kSizes)), impl_size_name);

class CompactorTest : public ::testing::TestWithParam<Shape> {};

TEST_P(CompactorTest, ReusesScratchAndKeepsInputs) {
  Runtime& rt = runtime();
  Compactor compactor(rt, GetParam());
  EXPECT_EQ(compactor.shape(), GetParam());
  for (const std::size_t n : {std::size_t{400000}, std::size_t{9}, std::size_t{400000}}) {
    const auto values = random_values<std::uint32_t>(n, 1, n);
    const std::size_t bytes = n * sizeof(std::uint32_t);
    cl::Buffer values_buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test values");
    cl::Buffer out = rt.buffer(CL_MEM_READ_WRITE, bytes, "test output");
    rt.queue().enqueueWriteBuffer(values_buffer, CL_TRUE, 0, bytes, values.data());
    Profiler profiler;
    // Values double as flags: keeps the ones.
    const std::size_t kept = compactor.keep_flagged(values_buffer, values_buffer, out, n, &profiler);
    EXPECT_FALSE(profiler.entries().empty());
    EXPECT_EQ(kept, static_cast<std::size_t>(std::count(values.begin(), values.end(), 1u)));
    std::vector<std::uint32_t> result(kept);
    if (kept) rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, kept * sizeof(std::uint32_t), result.data());
    EXPECT_EQ(result, std::vector<std::uint32_t>(kept, 1u));
    const std::size_t distinct = compactor.unique(values_buffer, out, n);
    result.resize(distinct);
    if (distinct) rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, distinct * sizeof(std::uint32_t), result.data());
    EXPECT_EQ(result, expected_unique(values));
    std::vector<std::uint32_t> values_after(n);
    rt.queue().enqueueReadBuffer(values_buffer, CL_TRUE, 0, bytes, values_after.data());
    EXPECT_EQ(values_after, values);
  }
}

TEST_P(CompactorTest, MismatchedInputsAreErrors) {
  Runtime& rt = runtime();
  Compactor compactor(rt, GetParam());
  cl::Buffer small = rt.buffer(CL_MEM_READ_WRITE, 64, "small");
  cl::Buffer large = rt.buffer(CL_MEM_READ_WRITE, 4000, "large");
  EXPECT_THROW(compactor.keep_flagged(large, small, large, 1000), Error);
  EXPECT_THROW(compactor.unique(large, small, 1000), Error);
  EXPECT_THROW(keep_flagged(rt, std::vector<std::uint32_t>(3), std::vector<std::uint32_t>(2), GetParam()), Error);
}

INSTANTIATE_TEST_SUITE_P(BothShapes, CompactorTest, ::testing::Values(Shape::Cpu, Shape::Gpu), shape_name);

TEST(ReferenceCompact, AnyThreadCount) {
  const auto values = random_values<std::uint32_t>(300007, 1, 14);
  for (const unsigned threads : {1u, 3u, 8u}) {
    std::vector<std::uint32_t> out(values.size());
    out.resize(reference::keep_flagged(values, values, out, threads));
    EXPECT_EQ(out, expected_keep(values, values)) << threads;
    out.assign(values.size(), 0);
    out.resize(reference::unique(values, out, threads));
    EXPECT_EQ(out, expected_unique(values)) << threads;
  }
  std::vector<std::uint32_t> too_short(3);
  EXPECT_THROW(reference::unique(values, too_short), Error);
  EXPECT_THROW(reference::keep_flagged(values, too_short, too_short), Error);
}

}  // namespace
}  // namespace splatcl::primitives::testing
