#pragma once
// Shared by the primitive tests: the implementations under test, the sizes, input patterns and one
// Runtime per test process.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "runtime/test_runtime.hpp"
#include "primitives/primitives.hpp"

namespace splatcl {
// Readable GetParam() in test listings.
inline void PrintTo(Shape shape, std::ostream* out) { *out << to_string(shape); }
}  // namespace splatcl

namespace splatcl::primitives::testing {

// The two device shapes (both run on whatever device the runtime picks, PoCL here) and the
// native reference.
enum class Impl { Cpu, Gpu, Reference };

inline const char* to_string(Impl impl) {
  switch (impl) {
    case Impl::Cpu: return "Cpu";
    case Impl::Gpu: return "Gpu";
    default: return "Reference";
  }
}

inline void PrintTo(Impl impl, std::ostream* out) { *out << to_string(impl); }

inline Shape shape_of(Impl impl) { return impl == Impl::Gpu ? Shape::Gpu : Shape::Cpu; }

inline constexpr Impl kImpls[] = {Impl::Cpu, Impl::Gpu, Impl::Reference};

// Empty, single, smaller than a work-group, not a multiple of any block, three GPU blocks of 1024
// with a partial last one (small enough for Oclgrind), and large enough for several CPU chunks,
// many blocks and two recursion levels.
inline constexpr std::size_t kSizes[] = {0, 1, 7, 1023, 3001, (std::size_t{1} << 20) + 3};

inline Runtime& runtime() { return splatcl::testing::shared_runtime(); }

// n values uniformly drawn from [0, mask] (mask of the form 2^k - 1), fixed seed.
template <class T>
std::vector<T> random_values(std::size_t n, std::uint64_t mask, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<T> values(n);
  for (auto& v : values) v = static_cast<T>(rng() & mask);
  return values;
}

// Test names for (Impl, size) parameters: "Cpu_n1023".
inline std::string impl_size_name(const ::testing::TestParamInfo<std::tuple<Impl, std::size_t>>& param_info) {
  return std::string(to_string(std::get<0>(param_info.param))) + "_n" + std::to_string(std::get<1>(param_info.param));
}

inline std::string shape_name(const ::testing::TestParamInfo<Shape>& param_info) {
  return splatcl::to_string(param_info.param);
}

}  // namespace splatcl::primitives::testing
