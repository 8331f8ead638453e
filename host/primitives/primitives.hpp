#pragma once
// Parallel primitives on OpenCL buffers: scan, stream compaction, LSD radix sort.
// Each has a CPU-shaped variant (one work-item per contiguous chunk, no barriers) and a GPU-shaped
// variant (work-groups with local memory), chosen by Shape (Auto = by device type). Their launch
// parameters come from the device's tuning record unless given (primitives/tuning.hpp). Native
// references of the same algorithms are in primitives/reference.hpp. Kernels: kernels/scan.cl,
// kernels/compact.cl, kernels/radix_sort.cl.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/device_vector.hpp"
#include "primitives/tuning.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::primitives {

enum class ScanKind { Exclusive, Inclusive };

// Scan of uint32 values (sums wrap modulo 2^32). Owns its scratch buffers, reused across calls.
class Scanner {
 public:
  // `parameters`: instead of the device's tuning record; validated against the device either way.
  explicit Scanner(Runtime& runtime, Shape shape = Shape::Auto, const std::optional<LaunchParameters>& parameters = std::nullopt);
  // out[0..n) = scan(in[0..n)); in and out may be the same buffer. Returns the total sum of in[0..n),
  // read back only when `read_total` is true (otherwise 0), so pipelines can stay asynchronous.
  std::uint32_t run(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind,
                    bool read_total = true, Profiler* profiler = nullptr);
  // After run(): a one-element device buffer holding the total, for kernels that need it.
  const cl::Buffer& total_buffer() const { return total_; }
  Shape shape() const { return shape_; }
  const LaunchParameters& parameters() const { return parameters_; }

 private:
  void run_cpu(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind, Profiler* profiler);
  // Scans one level of the GPU recursion; the block sums of level L are scanned by level L + 1.
  void run_gpu(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind, std::size_t level,
               Profiler* profiler);

  Runtime& runtime_;
  Shape shape_;
  LaunchParameters parameters_;
  cl::Buffer total_;
  std::vector<DeviceVector<cl_uint>> partials_;  // per recursion level (GPU shape) or chunk sums (CPU shape)
  cl::Kernel reduce_kernel_;          // CPU shape: chunk sums
  cl::Kernel scan_kernel_;            // CPU shape: chunk scans; GPU shape: block scans
  cl::Kernel add_kernel_;             // GPU shape: adds scanned block sums
};

// Stream compaction of uint32 values, stable. Owns its scratch.
class Compactor {
 public:
  // `parameters`: as for Scanner; its GPU shape scans block counts with the device's scan record.
  explicit Compactor(Runtime& runtime, Shape shape = Shape::Auto,
                     const std::optional<LaunchParameters>& parameters = std::nullopt);
  // out = values[i] for every i with flags[i] != 0, in order. Returns the count kept.
  std::size_t keep_flagged(const cl::Buffer& values, const cl::Buffer& flags, const cl::Buffer& out, std::size_t n,
                           Profiler* profiler = nullptr);
  // out = std::unique(values[0..n)) (first of each run of equal adjacent values). Returns the count.
  std::size_t unique(const cl::Buffer& values, const cl::Buffer& out, std::size_t n, Profiler* profiler = nullptr);
  Shape shape() const { return shape_; }
  const LaunchParameters& parameters() const { return parameters_; }

 private:
  // flags is not read in unique mode.
  std::size_t compact(const cl::Buffer& values, const cl::Buffer& flags, const cl::Buffer& out, std::size_t n,
                      bool unique_mode, Profiler* profiler);

  Runtime& runtime_;
  Shape shape_;
  LaunchParameters parameters_;
  DeviceVector<cl_uint> counts_;  // per chunk (CPU shape; the total after them) or per block (GPU shape)
  cl::Kernel count_kernel_, scatter_kernel_;
  std::optional<Scanner> block_scanner_;  // GPU shape: scans the block counts
};

enum class KeyType { U32, U64 };

// LSD radix sort of uint32 or uint64 keys, optionally carrying uint32 values; stable, so equal to
// std::stable_sort by key. Only the low `bits` bits of each key are sorted on (keys must fit in them
// for a full sort; higher bits are carried but ignored). Owns its scratch, reused across calls.
class RadixSorter {
 public:
  // `parameters`: as for Scanner; its GPU shape scans the histogram table with the device's scan record.
  RadixSorter(Runtime& runtime, KeyType key_type, bool with_values, Shape shape = Shape::Auto,
              const std::optional<LaunchParameters>& parameters = std::nullopt);
  // Sorts keys[0..n) (and values[0..n) alongside when with_values) in place.
  void sort(const cl::Buffer& keys, const cl::Buffer* values, std::size_t n, unsigned bits,
            Profiler* profiler = nullptr);
  Shape shape() const { return shape_; }
  const LaunchParameters& parameters() const { return parameters_; }

 private:
  // `values` is a dummy (value_scratch_) when sorting keys only.
  void sort_cpu(const cl::Buffer& keys, const cl::Buffer& values, std::size_t n, unsigned bits, Profiler* profiler);
  void sort_gpu(const cl::Buffer& keys, const cl::Buffer& values, std::size_t n, unsigned bits, Profiler* profiler);

  Runtime& runtime_;
  KeyType key_type_;
  bool with_values_;
  Shape shape_;
  LaunchParameters parameters_;
  cl::Buffer key_scratch_, value_scratch_;
  DeviceVector<cl_uint> histogram_;
  // CPU shape with an odd pass count (3 or more): a second scratch set, so that the passes can end
  // in the caller's buffers without a copy back.
  cl::Buffer key_spare_, value_spare_;
  std::size_t capacity_ = 0, spare_capacity_ = 0;
  // CPU shape: per-chunk histograms, scatter. GPU shape: block sort + histograms, scatter.
  cl::Kernel histogram_kernel_, scatter_kernel_;
  std::optional<Scanner> table_scanner_;  // GPU shape: scans the digit-major histogram table
};

// Host-vector conveniences (upload, run, download) used by tests and small callers.
std::vector<std::uint32_t> scan(Runtime& runtime, const std::vector<std::uint32_t>& in, ScanKind kind,
                                Shape shape = Shape::Auto);
std::vector<std::uint32_t> keep_flagged(Runtime& runtime, const std::vector<std::uint32_t>& values,
                                        const std::vector<std::uint32_t>& flags, Shape shape = Shape::Auto);
std::vector<std::uint32_t> unique(Runtime& runtime, const std::vector<std::uint32_t>& values, Shape shape = Shape::Auto);
void radix_sort(Runtime& runtime, std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>* values, unsigned bits,
                Shape shape = Shape::Auto);
void radix_sort(Runtime& runtime, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>* values, unsigned bits,
                Shape shape = Shape::Auto);

}  // namespace splatcl::primitives
