// splatcl bench primitives: every primitive in both kernel shapes against its native reference, the
// sorts against std and Boost.Compute, and the streaming-copy bandwidth that bounds them all.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "bench/bandwidth.hpp"
#include "bench/peer_cases.hpp"
#include "bench/suites.hpp"
#include "primitives/primitives.hpp"
#include "primitives/reference.hpp"

namespace splatcl::bench {
namespace {

namespace prim = splatcl::primitives;

// Fixed seed: the same inputs on every run and machine.
constexpr std::uint64_t kPrimitivesSeed = 0x5EED5EEDu;

std::vector<std::uint64_t> random_keys_64(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::uint64_t> keys(n);
  for (auto& key : keys) key = rng();
  return keys;
}

Json reference_threads() { return Json{{"threads", prim::reference::default_threads()}}; }

// The streaming floor of an LSD radix sort with 8-bit digits (the reference's): every pass reads and
// writes each key (and value) once.
std::uint64_t streaming_floor_bytes(std::size_t n, unsigned bits, std::size_t key_bytes, bool with_values) {
  const std::uint64_t passes = (bits + 7) / 8;
  return passes * 2 * n * (key_bytes + (with_values ? sizeof(std::uint32_t) : 0));
}

void bench_scan(Session& session, std::size_t n) {
  Runtime& runtime = session.runtime();
  const auto values = random_keys(n, 16, kPrimitivesSeed);
  std::vector<std::uint32_t> expected(n);
  prim::reference::scan(values, expected, prim::ScanKind::Exclusive);
  // The least memory traffic: read every value, write every sum.
  const Json scan_bytes{{"bytes", 8 * n}};

  const cl::Buffer in = upload(runtime, values, "scan input");
  const cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "scan output");
  for (const Shape shape : kBothShapes) {
    poison_buffer(runtime, out, n * sizeof(std::uint32_t));
    prim::Scanner scanner(runtime, shape);
    Profiler profiler;
    const Case c = opencl_case("scan-exclusive", shape, n, "elements", {}, scan_bytes);
    session.measure(c, {}, [&] {
      scanner.run(in, out, n, prim::ScanKind::Exclusive, false, &profiler);
      finish(runtime);
    }, &profiler);
    expect_same_output(describe(c), download<std::uint32_t>(runtime, out, n), expected);
  }

  std::vector<std::uint32_t> host_out(n);
  Case c = reference_case("scan-exclusive", n, "elements", {}, reference_threads());
  c.extra.update(scan_bytes);
  session.measure(c, {}, [&] { prim::reference::scan(values, host_out, prim::ScanKind::Exclusive); });
  expect_same_output(describe(c), host_out, expected);
}

void bench_compact_flagged(Session& session, std::size_t n) {
  Runtime& runtime = session.runtime();
  const auto values = random_keys(n, 32, kPrimitivesSeed + 1);
  const auto flags = random_keys(n, 1, kPrimitivesSeed + 2);  // about half kept
  const auto expected = prim::reference::keep_flagged(values, flags);
  const Json flagged_bytes{{"bytes", 8 * n + 4 * expected.size()}};  // values and flags in, kept values out

  const cl::Buffer values_buffer = upload(runtime, values, "compaction values");
  const cl::Buffer flags_buffer = upload(runtime, flags, "compaction flags");
  const cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "compaction output");
  for (const Shape shape : kBothShapes) {
    poison_buffer(runtime, out, n * sizeof(std::uint32_t));
    prim::Compactor compactor(runtime, shape);
    Profiler profiler;
    std::size_t kept = 0;
    const Case c = opencl_case("compact-flagged", shape, n, "elements", {}, flagged_bytes);
    session.measure(c, {}, [&] {
      kept = compactor.keep_flagged(values_buffer, flags_buffer, out, n, &profiler);
      finish(runtime);
    }, &profiler);
    expect_same_output(describe(c), download<std::uint32_t>(runtime, out, kept), expected);
  }

  std::vector<std::uint32_t> host_out(n);
  std::size_t kept = 0;
  Case c = reference_case("compact-flagged", n, "elements", {}, reference_threads());
  c.extra.update(flagged_bytes);
  session.measure(c, {}, [&] { kept = prim::reference::keep_flagged(values, flags, host_out); });
  host_out.resize(kept);
  expect_same_output(describe(c), host_out, expected);
}

void bench_compact_unique(Session& session, std::size_t n) {
  Runtime& runtime = session.runtime();
  // Sorted cluster keys: runs of equal keys, as the cluster stage produces them.
  auto keys = random_keys(n, kClusterKeyBits, kPrimitivesSeed + 3);
  std::sort(keys.begin(), keys.end());
  const auto expected = prim::reference::unique(keys);
  const Json unique_bytes{{"bytes", 4 * n + 4 * expected.size()}};  // keys in, unique keys out

  const cl::Buffer in = upload(runtime, keys, "unique input");
  const cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "unique output");
  for (const Shape shape : kBothShapes) {
    poison_buffer(runtime, out, n * sizeof(std::uint32_t));
    prim::Compactor compactor(runtime, shape);
    Profiler profiler;
    std::size_t kept = 0;
    const Case c = opencl_case("compact-unique", shape, n, "keys", {}, unique_bytes);
    session.measure(c, {}, [&] {
      kept = compactor.unique(in, out, n, &profiler);
      finish(runtime);
    }, &profiler);
    expect_same_output(describe(c), download<std::uint32_t>(runtime, out, kept), expected);
  }

  std::vector<std::uint32_t> host_out(n);
  std::size_t kept = 0;
  Case c = reference_case("compact-unique", n, "keys", {}, reference_threads());
  c.extra.update(unique_bytes);
  session.measure(c, {}, [&] { kept = prim::reference::unique(keys, host_out); });
  host_out.resize(kept);
  expect_same_output(describe(c), host_out, expected);

  measure_sort_peers(session, Case{"compact-unique", "", false, n, "keys"}, PeerWork::Unique, keys, expected);
}

// Sorts keys, and values alongside when `values` is not empty; the expected result is the stable sort
// by key, so key-value output checks stability too.
template <class Key>
void bench_radix_sort(Session& session, const std::string& name, const std::vector<Key>& keys,
                      const std::vector<std::uint32_t>& values, unsigned bits) {
  Runtime& runtime = session.runtime();
  const std::size_t n = keys.size();
  const bool with_values = !values.empty();
  const auto key_type = sizeof(Key) == 8 ? prim::KeyType::U64 : prim::KeyType::U32;
  const Json problem{{"bits", bits}};
  const Json sort_bytes{{"bytes", streaming_floor_bytes(n, bits, sizeof(Key), with_values)}};

  std::vector<Key> expected_keys = keys;
  std::vector<std::uint32_t> expected_values = values;
  prim::reference::radix_sort(expected_keys, with_values ? &expected_values : nullptr, bits);

  const cl::Buffer keys_in = upload(runtime, keys, "radix sort input keys");
  const cl::Buffer values_in = upload(runtime, values, "radix sort input values");
  const cl::Buffer keys_work = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(Key), "radix sort keys");
  const cl::Buffer values_work = runtime.buffer(CL_MEM_READ_WRITE, values.size() * sizeof(std::uint32_t), "radix sort values");
  for (const Shape shape : kBothShapes) {
    prim::RadixSorter sorter(runtime, key_type, with_values, shape);
    Profiler profiler;
    const Case c = opencl_case(name, shape, n, "keys", problem, sort_bytes);
    session.measure(
        c,
        [&] {
          copy_buffer(runtime, keys_in, keys_work, n * sizeof(Key));
          copy_buffer(runtime, values_in, values_work, values.size() * sizeof(std::uint32_t));
        },
        [&] {
          sorter.sort(keys_work, with_values ? &values_work : nullptr, n, bits, &profiler);
          finish(runtime);
        },
        &profiler);
    expect_same_output(describe(c) + " keys", download<Key>(runtime, keys_work, n), expected_keys);
    expect_same_output(describe(c) + " values", download<std::uint32_t>(runtime, values_work, values.size()), expected_values);
  }

  prim::reference::RadixSorter sorter;
  std::vector<Key> host_keys;
  std::vector<std::uint32_t> host_values;
  Case c = reference_case(name, n, "keys", problem, reference_threads());
  c.extra.update(sort_bytes);
  session.measure(
      c,
      [&] {
        host_keys = keys;
        host_values = values;
      },
      [&] { sorter.sort(std::span<Key>(host_keys), std::span<std::uint32_t>(host_values), bits); });
  expect_same_output(describe(c) + " keys", host_keys, expected_keys);
  expect_same_output(describe(c) + " values", host_values, expected_values);

  if constexpr (sizeof(Key) == 4) {
    if (!with_values) measure_sort_peers(session, Case{name, "", false, n, "keys", problem}, PeerWork::Sort, keys, expected_keys);
  }
}

// Radix sort then unique of 20-bit keys: the distinct cluster keys of a frame.
void bench_sort_unique(Session& session, std::size_t n) {
  Runtime& runtime = session.runtime();
  const auto keys = random_keys(n, kClusterKeyBits, kPrimitivesSeed + 4);
  std::vector<std::uint32_t> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  const auto expected = prim::reference::unique(sorted);
  const Json problem{{"bits", kClusterKeyBits}};

  // The sort's floor, then the sorted keys read once more and the unique ones written.
  const Json sort_unique_bytes{{"bytes", streaming_floor_bytes(n, kClusterKeyBits, 4, false) + 4 * n + 4 * expected.size()}};
  const cl::Buffer keys_in = upload(runtime, keys, "sort-unique input");
  const cl::Buffer keys_work = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "sort-unique keys");
  const cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, n * sizeof(std::uint32_t), "sort-unique output");
  for (const Shape shape : kBothShapes) {
    poison_buffer(runtime, out, n * sizeof(std::uint32_t));
    prim::RadixSorter sorter(runtime, prim::KeyType::U32, false, shape);
    prim::Compactor compactor(runtime, shape);
    Profiler profiler;
    std::size_t kept = 0;
    const Case c = opencl_case("sort-unique", shape, n, "keys", problem, sort_unique_bytes);
    session.measure(
        c, [&] { copy_buffer(runtime, keys_in, keys_work, n * sizeof(std::uint32_t)); },
        [&] {
          sorter.sort(keys_work, nullptr, n, kClusterKeyBits, &profiler);
          kept = compactor.unique(keys_work, out, n, &profiler);
          finish(runtime);
        },
        &profiler);
    expect_same_output(describe(c), download<std::uint32_t>(runtime, out, kept), expected);
  }

  prim::reference::RadixSorter sorter;
  std::vector<std::uint32_t> host_keys;
  std::vector<std::uint32_t> host_out(n);
  std::size_t kept = 0;
  Case c = reference_case("sort-unique", n, "keys", problem, reference_threads());
  c.extra.update(sort_unique_bytes);
  session.measure(c, [&] { host_keys = keys; }, [&] {
    sorter.sort(std::span<std::uint32_t>(host_keys), {}, kClusterKeyBits);
    kept = prim::reference::unique(host_keys, host_out);
  });
  host_out.resize(kept);
  expect_same_output(describe(c), host_out, expected);

  measure_sort_peers(session, Case{"sort-unique", "", false, n, "keys", problem}, PeerWork::SortUnique, keys, expected);
}

}  // namespace

void run_primitives_suite(Session& session) {
  // --quick: 64k elements instead of --size.
  const auto n = static_cast<std::size_t>(scaled(session, session.options().quick ? 1u << 16 : session.options().size));
  bench_scan(session, n);
  bench_compact_flagged(session, n);
  bench_compact_unique(session, n);
  bench_radix_sort<std::uint32_t>(session, "radix-sort-u32", random_keys(n, kClusterKeyBits, kPrimitivesSeed + 5), {}, kClusterKeyBits);
  bench_radix_sort<std::uint32_t>(session, "radix-sort-u32", random_keys(n, 32, kPrimitivesSeed + 6), {}, 32);
  std::vector<std::uint32_t> indices(n);
  std::iota(indices.begin(), indices.end(), 0u);
  bench_radix_sort<std::uint32_t>(session, "radix-sort-kv", random_keys(n, 32, kPrimitivesSeed + 7), indices, 32);
  bench_radix_sort<std::uint64_t>(session, "radix-sort-u64", random_keys_64(n, kPrimitivesSeed + 8), {}, 64);
  bench_sort_unique(session, n);
  measure_ceilings(session, session.options().quick ? kQuickStreamArrayBytes : kStreamArrayBytes);
}

}  // namespace splatcl::bench
