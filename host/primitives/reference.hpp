#pragma once
// Native C++ references of the primitives, the same algorithms as the CPU-shaped kernels: each
// thread takes one contiguous chunk, chunk results are combined by a scan, no atomics. Used by the
// tests as independent implementations and by the benchmarks as the native baseline.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "primitives/primitives.hpp"

namespace splatcl::primitives::reference {

// Threads used when a function is given threads = 0: the CPUs of the process's affinity mask (usable_cpus).
unsigned default_threads();

// out = scan(in); in and out may be the same memory. Returns the total (wrapping modulo 2^32).
std::uint32_t scan(std::span<const std::uint32_t> in, std::span<std::uint32_t> out, ScanKind kind,
                   unsigned threads = 0);
// Stable compaction into out (at least values.size() long); return the count written.
std::size_t keep_flagged(std::span<const std::uint32_t> values, std::span<const std::uint32_t> flags,
                         std::span<std::uint32_t> out, unsigned threads = 0);
std::size_t unique(std::span<const std::uint32_t> values, std::span<std::uint32_t> out, unsigned threads = 0);

// LSD radix sort, 8-bit digits (the last narrower), per-thread histograms and stable scatter.
// Keeps its scratch across calls, like the device sorter.
class RadixSorter {
 public:
  explicit RadixSorter(unsigned threads = 0);
  // Sorts keys (and values alongside, unless values is empty) by their low `bits` bits, stably.
  void sort(std::span<std::uint32_t> keys, std::span<std::uint32_t> values, unsigned bits);
  void sort(std::span<std::uint64_t> keys, std::span<std::uint32_t> values, unsigned bits);

 private:
  template <class Key>
  void sort_keys(std::span<Key> keys, std::span<std::uint32_t> values, unsigned bits, std::vector<Key>& key_scratch);

  unsigned threads_;
  std::vector<std::uint32_t> key_scratch_32_, value_scratch_;
  std::vector<std::uint64_t> key_scratch_64_;
  std::vector<std::uint32_t> histograms_;
};

// Vector conveniences.
std::vector<std::uint32_t> scan(const std::vector<std::uint32_t>& in, ScanKind kind);
std::vector<std::uint32_t> keep_flagged(const std::vector<std::uint32_t>& values,
                                        const std::vector<std::uint32_t>& flags);
std::vector<std::uint32_t> unique(const std::vector<std::uint32_t>& values);
void radix_sort(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>* values, unsigned bits);
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>* values, unsigned bits);

}  // namespace splatcl::primitives::reference
