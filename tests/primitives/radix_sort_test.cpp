#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"
#include "primitives_test_support.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives::testing {
namespace {

struct SortConfig {
  KeyType key_type;
  unsigned bits;
  bool with_values;
  const char* name;
};

// Even and odd pass counts on both shapes (8-bit CPU digits, 4-bit GPU digits), narrow last digits,
// a single pass, both key widths, with and without values.
constexpr SortConfig kConfigs[] = {
    {KeyType::U32, 32, true, "u32_bits32_values"}, {KeyType::U32, 20, true, "u32_bits20_values"},
    {KeyType::U32, 9, false, "u32_bits9_keys"},    {KeyType::U32, 1, true, "u32_bits1_values"},
    {KeyType::U64, 64, true, "u64_bits64_values"}, {KeyType::U64, 40, false, "u64_bits40_keys"},
    {KeyType::U64, 8, true, "u64_bits8_values"},
};

void PrintTo(const SortConfig& config, std::ostream* out) { *out << config.name; }

std::uint64_t low_mask(unsigned bits) { return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1; }

template <class Key>
struct SortCase {
  std::string name;
  std::vector<Key> keys;
};

// Keys within `bits` (random, all maximal, sorted, reverse sorted, half maximal), and when bits is
// narrower than the key, full-width keys of which only the low bits count.
template <class Key>
std::vector<SortCase<Key>> sort_cases(std::size_t n, unsigned bits) {
  const std::uint64_t mask = low_mask(bits);
  std::vector<SortCase<Key>> cases;
  cases.push_back({"random", random_values<Key>(n, mask, 21)});
  cases.push_back({"all maximal", std::vector<Key>(n, static_cast<Key>(mask))});
  auto sorted = random_values<Key>(n, mask, 22);
  std::sort(sorted.begin(), sorted.end());
  cases.push_back({"sorted", sorted});
  std::reverse(sorted.begin(), sorted.end());
  cases.push_back({"reverse sorted", sorted});
  auto half_max = random_values<Key>(n, mask, 23);
  for (std::size_t i = 0; i < n; i += 2) half_max[i] = static_cast<Key>(mask);
  cases.push_back({"half maximal", half_max});
  if (bits < sizeof(Key) * 8) cases.push_back({"high bits ignored", random_values<Key>(n, ~std::uint64_t{0}, 24)});
  return cases;
}

template <class Key>
void check_sort(Impl impl, const SortConfig& config, std::size_t n) {
  const Key mask = static_cast<Key>(low_mask(config.bits));
  for (auto& sort_case : sort_cases<Key>(n, config.bits)) {
    SCOPED_TRACE(sort_case.name);
    std::vector<Key> keys = sort_case.keys;
    std::vector<std::uint32_t> values(n);
    std::iota(values.begin(), values.end(), std::uint32_t{0});
    // std::stable_sort by the sorted bits of (key, original index) pairs.
    std::vector<std::pair<Key, std::uint32_t>> expected(n);
    for (std::size_t i = 0; i < n; ++i) expected[i] = {keys[i], values[i]};
    std::stable_sort(expected.begin(), expected.end(),
                     [&](const auto& a, const auto& b) { return (a.first & mask) < (b.first & mask); });
    std::vector<Key> expected_keys(n);
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) std::tie(expected_keys[i], order[i]) = expected[i];

    std::vector<std::uint32_t>* values_arg = config.with_values ? &values : nullptr;
    if (impl == Impl::Reference) {
      reference::radix_sort(keys, values_arg, config.bits);
    } else {
      radix_sort(runtime(), keys, values_arg, config.bits, shape_of(impl));
    }
    EXPECT_EQ(keys, expected_keys);
    if (config.with_values) {
      EXPECT_EQ(values, order);
    }
  }
}

class RadixSortTest : public ::testing::TestWithParam<std::tuple<Impl, std::size_t, SortConfig>> {};

TEST_P(RadixSortTest, MatchesStdStableSort) {
  const auto [impl, n, config] = GetParam();
  if (config.key_type == KeyType::U64) {
    check_sort<std::uint64_t>(impl, config, n);
  } else {
    check_sort<std::uint32_t>(impl, config, n);
  }
}

INSTANTIATE_TEST_SUITE_P(AllImplsSizesAndKeys, RadixSortTest,
                         ::testing::Combine(::testing::ValuesIn(kImpls), ::testing::ValuesIn(kSizes),
                                            ::testing::ValuesIn(kConfigs)),
                         [](const auto& param_info) {
                           return std::string(to_string(std::get<0>(param_info.param))) + "_n" +
                                  std::to_string(std::get<1>(param_info.param)) + "_" +
                                  std::get<2>(param_info.param).name;
                         });

class RadixSorterTest : public ::testing::TestWithParam<Shape> {};

// One sorter through growing and shrinking sizes and changing bit counts, so that scratch reuse,
// the spare scratch and the single-pass copy are exercised on the same object.
TEST_P(RadixSorterTest, ReusesScratchAcrossSizesAndBits) {
  Runtime& rt = runtime();
  RadixSorter sorter(rt, KeyType::U32, true, GetParam());
  EXPECT_EQ(sorter.shape(), GetParam());
  const std::pair<std::size_t, unsigned> runs[] = {{70000, 20}, {300000, 32}, {1000, 8}, {300000, 20}, {5, 0}};
  for (const auto& [n, bits] : runs) {
    SCOPED_TRACE(std::to_string(n) + " keys, " + std::to_string(bits) + " bits");
    const auto keys = random_values<std::uint32_t>(n, low_mask(bits), n + bits);
    std::vector<std::uint32_t> values(n);
    std::iota(values.begin(), values.end(), std::uint32_t{0});
    const std::size_t bytes = n * sizeof(std::uint32_t);
    cl::Buffer key_buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test keys");
    cl::Buffer value_buffer = rt.buffer(CL_MEM_READ_WRITE, bytes, "test values");
    rt.queue().enqueueWriteBuffer(key_buffer, CL_TRUE, 0, bytes, keys.data());
    rt.queue().enqueueWriteBuffer(value_buffer, CL_TRUE, 0, bytes, values.data());
    Profiler profiler;
    sorter.sort(key_buffer, &value_buffer, n, bits, &profiler);
    EXPECT_EQ(profiler.entries().empty(), bits == 0);
    std::vector<std::uint32_t> sorted_keys(n), sorted_values(n);
    rt.queue().enqueueReadBuffer(key_buffer, CL_TRUE, 0, bytes, sorted_keys.data());
    rt.queue().enqueueReadBuffer(value_buffer, CL_TRUE, 0, bytes, sorted_values.data());
    std::vector<std::uint32_t> order = values;
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    if (bits == 0) order = values;  // nothing to sort on: left as is
    std::vector<std::uint32_t> expected_keys(n);
    for (std::size_t i = 0; i < n; ++i) expected_keys[i] = keys[order[i]];
    EXPECT_EQ(sorted_keys, expected_keys);
    EXPECT_EQ(sorted_values, order);
  }
}

TEST_P(RadixSorterTest, InvalidRequestsAreErrors) {
  Runtime& rt = runtime();
  cl::Buffer buffer = rt.buffer(CL_MEM_READ_WRITE, 4096, "test buffer");
  RadixSorter with_values(rt, KeyType::U32, true, GetParam());
  RadixSorter keys_only(rt, KeyType::U64, false, GetParam());
  EXPECT_THROW(with_values.sort(buffer, nullptr, 100, 32), Error);
  EXPECT_THROW(keys_only.sort(buffer, &buffer, 100, 32), Error);
  EXPECT_THROW(with_values.sort(buffer, &buffer, 100, 33), Error);
  EXPECT_THROW(keys_only.sort(buffer, nullptr, 100, 65), Error);
  EXPECT_THROW(keys_only.sort(buffer, nullptr, 1000, 64), Error);  // 8000 bytes of keys needed
  std::vector<std::uint32_t> keys(10), values(9);
  EXPECT_THROW(radix_sort(rt, keys, &values, 32, GetParam()), Error);
}

INSTANTIATE_TEST_SUITE_P(BothShapes, RadixSorterTest, ::testing::Values(Shape::Cpu, Shape::Gpu), shape_name);

TEST(ReferenceRadixSort, AnyThreadCountAndErrors) {
  const auto keys = random_values<std::uint32_t>(400003, 0xFFFFF, 25);
  std::vector<std::uint32_t> order(keys.size());
  std::iota(order.begin(), order.end(), std::uint32_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  for (const unsigned threads : {1u, 3u, 8u}) {
    reference::RadixSorter sorter(threads);
    std::vector<std::uint32_t> sorted_keys = keys, values(keys.size());
    std::iota(values.begin(), values.end(), std::uint32_t{0});
    sorter.sort(sorted_keys, values, 20);
    EXPECT_EQ(values, order) << threads;
  }
  reference::RadixSorter sorter;
  std::vector<std::uint32_t> three(3), two(2);
  EXPECT_THROW(sorter.sort(three, two, 32), Error);
  EXPECT_THROW(sorter.sort(three, {}, 33), Error);
}

}  // namespace
}  // namespace splatcl::primitives::testing
