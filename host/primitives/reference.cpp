#include "primitives/reference.hpp"

#include <algorithm>
#include <barrier>
#include <cstring>
#include <cstdint>
#include <string>
#include <thread>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "io/cpu_set.hpp"
#include "primitives/launch.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives::reference {
namespace {

// Below this many elements per thread, another thread costs more to start than it saves.
constexpr std::size_t kMinChunk = std::size_t{1} << 15;
constexpr unsigned kDigitBits = 8;
constexpr std::size_t kRadix = std::size_t{1} << kDigitBits;

unsigned thread_count(unsigned requested, std::size_t n) {
  const std::size_t wanted = requested ? requested : default_threads();
  return static_cast<unsigned>(std::clamp<std::size_t>(n / kMinChunk, 1, wanted));
}

// chunk_begin(n, chunks, c): first index of chunk c when n items are split into `chunks` nearly
// equal parts, one source with the kernels.
using std::size_t;
#include "../../kernels/common.h"

// Runs body(thread_index) on `threads` threads, the caller's being index 0, and joins them.
template <class Body>
void run_threads(unsigned threads, const Body& body) {
  std::vector<std::jthread> workers;
  workers.reserve(threads - 1);
  for (unsigned t = 1; t < threads; ++t) workers.emplace_back(body, t);
  body(0u);
}

void require_output(std::size_t out_size, std::size_t n, const char* what) {
  if (out_size < n)
    throw Error(std::string(what) + ": output holds " + std::to_string(out_size) + " elements, " +
                std::to_string(n) + " needed");
}

// Two-phase stable compaction: count per chunk, then write from the scanned counts. kept(i) says
// whether element i stays. Writes are branch-free up to the chunk's last kept element (as in
// kernels/compact.cl): a dropped element's write is overwritten by the next kept one.
template <class Kept>
std::size_t compact(std::span<const std::uint32_t> values, std::span<std::uint32_t> out, unsigned threads,
                    const Kept& kept) {
  const std::size_t n = values.size();
  const unsigned chunks = thread_count(threads, n);
  std::vector<std::size_t> counts(chunks);
  std::barrier sync(chunks);
  run_threads(chunks, [&](unsigned c) {
    const std::size_t begin = chunk_begin(n, chunks, c), end = chunk_begin(n, chunks, c + 1);
    std::size_t count = 0;
    for (std::size_t i = begin; i < end; ++i) count += kept(i);
    counts[c] = count;
    sync.arrive_and_wait();
    std::size_t position = 0;
    for (unsigned k = 0; k < c; ++k) position += counts[k];
    std::size_t last_kept = end;
    while (last_kept > begin && !kept(last_kept - 1)) --last_kept;
    for (std::size_t i = begin; i < last_kept; ++i) {
      out[position] = values[i];
      position += kept(i);
    }
  });
  std::size_t total = 0;
  for (const auto count : counts) total += count;
  return total;
}

// Stores one cache line (kLineBytes, 64-byte aligned `target`) bypassing the cache where the
// compiler offers streaming stores (x86-64): the scatter's output is not read again before the
// next pass, so fetching its lines into the cache first is wasted traffic.
constexpr std::size_t kLineBytes = 64;

inline void stream_line(void* target, const void* source) {
#if defined(__SSE2__)
  auto* to = static_cast<__m128i*>(target);
  const auto* from = static_cast<const __m128i*>(source);
  for (std::size_t k = 0; k < kLineBytes / sizeof(__m128i); ++k) _mm_stream_si128(to + k, _mm_loadu_si128(from + k));
#else
  std::memcpy(target, source, kLineBytes);
#endif
}

// Write combining, as in kernels/radix_sort.cl: a digit's elements are staged and every full
// cache line of output leaves in one go with streaming stores. Lines follow the memory (a caller's
// array need not start on one): kRing staged slots per digit, indexed so that a line is contiguous.
constexpr std::size_t kRing = 16;

template <class T>
class StagedOutput {
 public:
  // `staged` holds kRing slots per digit.
  StagedOutput(T* out, std::vector<T>& staged)
      : out_(out), staged_(staged.data()), phase_(reinterpret_cast<std::uintptr_t>(out) / sizeof(T) % kRun) {}

  // Stages `value` for output `position` of digit d and stores the line it completes; positions
  // before `first` (the chunk's first of this digit) belong to another chunk and are not written.
  void put(std::size_t d, std::size_t position, T value, std::size_t first) {
    staged_[slot(d, position)] = value;
    if ((position + phase_ + 1) % kRun != 0) return;
    if (position + 1 < first + kRun) {
      store(d, first, position + 1);
    } else {
      stream_line(out_ + position + 1 - kRun, staged_ + slot(d, position + 1 - kRun));
    }
  }

  // Stores digit d's staged positions after its last full line, up to `end`.
  void finish(std::size_t d, std::size_t first, std::size_t end) {
    const std::size_t after_last_line = (end + phase_) % kRun;
    store(d, end - std::min(after_last_line, end - first), end);
  }

 private:
  static constexpr std::size_t kRun = kLineBytes / sizeof(T);
  static_assert(kRing % kRun == 0);

  std::size_t slot(std::size_t d, std::size_t position) const { return d * kRing + (position + phase_) % kRing; }

  void store(std::size_t d, std::size_t from, std::size_t to) {
    for (std::size_t q = from; q < to; ++q) out_[q] = staged_[slot(d, q)];
  }

  T* out_;
  T* staged_;
  std::size_t phase_;  // elements from a cache line's start to out_[0]
};

// A sorting thread's working memory, allocated before the threads start so that none of them can
// fail between barriers.
template <class Key>
struct SortThreadScratch {
  explicit SortThreadScratch(bool with_values)
      : staged_keys(kRadix * kRing), staged_values(with_values ? kRadix * kRing : 0), next(kRadix), first(kRadix) {}
  std::vector<Key> staged_keys;
  std::vector<std::uint32_t> staged_values;
  std::vector<std::size_t> next;   // per digit: count, then next output position
  std::vector<std::size_t> first;  // per digit: the chunk's first output position
};

// Moves [begin, end) to scratch.next[digit]++ in input order, for digits below `radix`
// (values_in/out are null when sorting keys only).
template <class Key, class DigitOf>
void scatter_chunk(const Key* keys_in, Key* keys_out, const std::uint32_t* values_in, std::uint32_t* values_out,
                   std::size_t begin, std::size_t end, const DigitOf& digit_of, std::size_t radix,
                   SortThreadScratch<Key>& scratch) {
  auto& next = scratch.next;
  auto& first = scratch.first;
  std::copy_n(next.begin(), radix, first.begin());
  StagedOutput<Key> keys(keys_out, scratch.staged_keys);
  StagedOutput<std::uint32_t> values(values_out, scratch.staged_values);
  for (std::size_t i = begin; i < end; ++i) {
    const Key key = keys_in[i];
    const std::size_t d = digit_of(key);
    const std::size_t position = next[d]++;
    keys.put(d, position, key, first[d]);
    if (values_in) values.put(d, position, values_in[i], first[d]);
  }
  for (std::size_t d = 0; d < radix; ++d) {
    keys.finish(d, first[d], next[d]);
    if (values_in) values.finish(d, first[d], next[d]);
  }
#if defined(__SSE2__)
  _mm_sfence();  // streaming stores are weakly ordered: publish them before the threads synchronise
#endif
}

}  // namespace

unsigned default_threads() { return usable_cpus(); }

std::uint32_t scan(std::span<const std::uint32_t> in, std::span<std::uint32_t> out, ScanKind kind, unsigned threads) {
  require_output(out.size(), in.size(), "reference scan");
  const std::size_t n = in.size();
  const unsigned chunks = thread_count(threads, n);
  const bool inclusive = kind == ScanKind::Inclusive;
  std::vector<std::uint32_t> sums(chunks);
  std::barrier sync(chunks);
  run_threads(chunks, [&](unsigned c) {
    const std::size_t begin = chunk_begin(n, chunks, c), end = chunk_begin(n, chunks, c + 1);
    std::uint32_t running = 0;
    if (chunks > 1) {
      for (std::size_t i = begin; i < end; ++i) running += in[i];
      sums[c] = running;
      sync.arrive_and_wait();
      running = 0;
      for (unsigned k = 0; k < c; ++k) running += sums[k];
    }
    // Loops split by kind so that each stays a plain dependency chain.
    if (inclusive) {
      for (std::size_t i = begin; i < end; ++i) out[i] = running += in[i];
    } else {
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t value = in[i];
        out[i] = running;
        running += value;
      }
    }
    if (c == chunks - 1) sums[c] = running;
  });
  return n == 0 ? 0 : sums[chunks - 1];
}

std::size_t keep_flagged(std::span<const std::uint32_t> values, std::span<const std::uint32_t> flags,
                         std::span<std::uint32_t> out, unsigned threads) {
  if (flags.size() != values.size())
    throw Error("reference keep_flagged: " + std::to_string(values.size()) + " values but " +
                std::to_string(flags.size()) + " flags");
  require_output(out.size(), values.size(), "reference keep_flagged");
  return compact(values, out, threads, [&](std::size_t i) { return flags[i] != 0; });
}

std::size_t unique(std::span<const std::uint32_t> values, std::span<std::uint32_t> out, unsigned threads) {
  require_output(out.size(), values.size(), "reference unique");
  return compact(values, out, threads, [&](std::size_t i) { return i == 0 || values[i] != values[i - 1]; });
}

RadixSorter::RadixSorter(unsigned threads) : threads_(threads) {}

void RadixSorter::sort(std::span<std::uint32_t> keys, std::span<std::uint32_t> values, unsigned bits) {
  sort_keys(keys, values, bits, key_scratch_32_);
}

void RadixSorter::sort(std::span<std::uint64_t> keys, std::span<std::uint32_t> values, unsigned bits) {
  sort_keys(keys, values, bits, key_scratch_64_);
}

template <class Key>
void RadixSorter::sort_keys(std::span<Key> keys, std::span<std::uint32_t> values, unsigned bits,
                            std::vector<Key>& key_scratch) {
  constexpr unsigned key_bits = sizeof(Key) * 8;
  if (bits > key_bits)
    throw Error("reference radix sort: " + std::to_string(bits) + " bits requested for " + std::to_string(key_bits) +
                "-bit keys");
  const bool with_values = !values.empty();
  if (with_values && values.size() != keys.size())
    throw Error("reference radix sort: " + std::to_string(keys.size()) + " keys but " +
                std::to_string(values.size()) + " values");
  const std::size_t n = keys.size();
  if (n <= 1 || bits == 0) return;
  const auto passes = static_cast<unsigned>((bits + kDigitBits - 1) / kDigitBits);
  // Scratch and spare halves (see detail::radix_pass_target); the spare only for odd pass counts.
  const std::size_t scratch_size = passes % 2 == 1 && passes > 1 ? 2 * n : n;
  if (key_scratch.size() < scratch_size) key_scratch.resize(scratch_size);
  if (with_values && value_scratch_.size() < scratch_size) value_scratch_.resize(scratch_size);
  const auto target = [&](unsigned pass, auto* caller, auto* scratch) {
    switch (detail::radix_pass_target(pass, passes)) {
      case detail::RadixTarget::Caller: return caller;
      case detail::RadixTarget::Scratch: return scratch;
      default: return scratch + n;
    }
  };
  const unsigned chunks = thread_count(threads_, n);
  histograms_.resize(kRadix * chunks);
  std::vector<SortThreadScratch<Key>> thread_scratch(chunks, SortThreadScratch<Key>(with_values));
  std::barrier sync(chunks);
  run_threads(chunks, [&](unsigned c) {
    const std::size_t begin = chunk_begin(n, chunks, c), end = chunk_begin(n, chunks, c + 1);
    auto& next = thread_scratch[c].next;
    Key* keys_in = keys.data();
    std::uint32_t* values_in = with_values ? values.data() : nullptr;
    for (unsigned pass = 0; pass < passes; ++pass) {
      Key* keys_out = target(pass, keys.data(), key_scratch.data());
      std::uint32_t* values_out = with_values ? target(pass, values.data(), value_scratch_.data()) : nullptr;
      const unsigned shift = pass * kDigitBits;
      const std::size_t radix = std::size_t{1} << std::min(kDigitBits, bits - shift);
      const auto digit_of = [&](Key key) { return static_cast<std::size_t>(key >> shift) & (radix - 1); };
      // Digit-major table: a scan over it gives each (digit, chunk) its first output position.
      std::fill_n(next.begin(), radix, 0);
      for (std::size_t i = begin; i < end; ++i) ++next[digit_of(keys_in[i])];
      for (std::size_t d = 0; d < radix; ++d) histograms_[d * chunks + c] = static_cast<std::uint32_t>(next[d]);
      sync.arrive_and_wait();
      std::size_t running = 0;
      for (std::size_t d = 0; d < radix; ++d) {
        for (unsigned k = 0; k < chunks; ++k) {
          if (k == c) next[d] = running;
          running += histograms_[d * chunks + k];
        }
      }
      scatter_chunk(keys_in, keys_out, values_in, values_out, begin, end, digit_of, radix, thread_scratch[c]);
      // The next pass reads what every thread wrote, and rewrites the table.
      sync.arrive_and_wait();
      keys_in = keys_out;
      values_in = values_out;
    }
    if (passes == 1) {
      // A single pass cannot write where it reads: copy this chunk's share of the result back.
      std::copy(keys_in + begin, keys_in + end, keys.data() + begin);
      if (with_values) std::copy(values_in + begin, values_in + end, values.data() + begin);
    }
  });
}

std::vector<std::uint32_t> scan(const std::vector<std::uint32_t>& in, ScanKind kind) {
  std::vector<std::uint32_t> out(in.size());
  reference::scan(in, out, kind);
  return out;
}

std::vector<std::uint32_t> keep_flagged(const std::vector<std::uint32_t>& values,
                                        const std::vector<std::uint32_t>& flags) {
  std::vector<std::uint32_t> out(values.size());
  out.resize(reference::keep_flagged(values, flags, out));
  return out;
}

std::vector<std::uint32_t> unique(const std::vector<std::uint32_t>& values) {
  std::vector<std::uint32_t> out(values.size());
  out.resize(reference::unique(values, out));
  return out;
}

void radix_sort(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>* values, unsigned bits) {
  RadixSorter().sort(keys, values ? std::span<std::uint32_t>(*values) : std::span<std::uint32_t>(), bits);
}

void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>* values, unsigned bits) {
  RadixSorter().sort(keys, values ? std::span<std::uint32_t>(*values) : std::span<std::uint32_t>(), bits);
}

}  // namespace splatcl::primitives::reference
