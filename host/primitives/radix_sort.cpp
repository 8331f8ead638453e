#include <algorithm>
#include <limits>
#include <string>
#include <utility>

#include "primitives/launch.hpp"
#include "primitives/primitives.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives {
namespace {

#include "../../kernels/primitives_layout.h"

// The GPU kernels' digit width, one source with them.
constexpr unsigned kGpuDigitBits = GPU_DIGIT_BITS;

std::size_t key_bytes(KeyType key_type) { return key_type == KeyType::U64 ? sizeof(cl_ulong) : sizeof(cl_uint); }

std::string sort_options(KeyType key_type, bool with_values, const LaunchParameters& parameters) {
  return detail::group_options(parameters) + (key_type == KeyType::U64 ? " -DKEY_T=ulong" : " -DKEY_T=uint") +
         (with_values ? " -DWITH_VALUES=1" : " -DWITH_VALUES=0") + " -DCPU_RADIX_BITS=" + std::to_string(parameters.digit_bits) +
         " -DGPU_ITEM_KEYS=" + std::to_string(parameters.items_per_work_item);
}

}  // namespace

RadixSorter::RadixSorter(Runtime& runtime, KeyType key_type, bool with_values, Shape shape,
                         const std::optional<LaunchParameters>& parameters)
    : runtime_(runtime),
      key_type_(key_type),
      with_values_(with_values),
      shape_(runtime.resolve(shape)),
      parameters_(detail::launch_parameters(runtime, Primitive::RadixSort, shape_, parameters, key_bytes(key_type), with_values)),
      histogram_(runtime, "radix sort histograms") {
  const std::string options = sort_options(key_type_, with_values_, parameters_);
  if (shape_ == Shape::Cpu) {
    histogram_kernel_ = runtime_.kernel("radix_sort.cl", "radix_histogram_cpu", options);
    scatter_kernel_ = runtime_.kernel("radix_sort.cl", "radix_scatter_cpu", options);
  } else {
    histogram_kernel_ = runtime_.kernel("radix_sort.cl", "radix_block_sort_gpu", options);
    scatter_kernel_ = runtime_.kernel("radix_sort.cl", "radix_scatter_gpu", options);
    const auto group = static_cast<std::size_t>(parameters_.group_size);
    validate_built_kernel(histogram_kernel_, "radix_block_sort_gpu", group, runtime_.info());
    validate_built_kernel(scatter_kernel_, "radix_scatter_gpu", group, runtime_.info());
    table_scanner_.emplace(runtime_, Shape::Gpu);
  }
  value_scratch_ = runtime_.buffer(CL_MEM_READ_WRITE, 0, "radix sort value scratch");
}

void RadixSorter::sort(const cl::Buffer& keys, const cl::Buffer* values, std::size_t n, unsigned bits,
                       Profiler* profiler) {
  const unsigned key_bits = static_cast<unsigned>(key_bytes(key_type_) * 8);
  if (bits > key_bits)
    throw Error("radix sort: " + std::to_string(bits) + " bits requested for " + std::to_string(key_bits) +
                "-bit keys");
  if (with_values_ != (values != nullptr))
    throw Error(with_values_ ? "radix sort: this sorter carries values but none were given"
                             : "radix sort: values given to a keys-only sorter");
  if (n > std::numeric_limits<cl_uint>::max())
    throw Error("radix sort: " + std::to_string(n) + " keys exceed the 2^32 - 1 supported");
  require_bytes(keys, n * key_bytes(key_type_), "radix sort keys");
  if (values) require_bytes(*values, n * sizeof(cl_uint), "radix sort values");
  if (n <= 1 || bits == 0) return;
  try {
    if (n > capacity_) {
      key_scratch_ = runtime_.buffer(CL_MEM_READ_WRITE, n * key_bytes(key_type_), "radix sort key scratch");
      if (with_values_)
        value_scratch_ = runtime_.buffer(CL_MEM_READ_WRITE, n * sizeof(cl_uint), "radix sort value scratch");
      capacity_ = n;
    }
    const cl::Buffer& values_or_dummy = values ? *values : value_scratch_;
    if (shape_ == Shape::Cpu) {
      sort_cpu(keys, values_or_dummy, n, bits, profiler);
    } else {
      sort_gpu(keys, values_or_dummy, n, bits, profiler);
    }
  } catch (...) {
    rethrow_as_error("radix sort of " + std::to_string(n) + " keys");
  }
}

void RadixSorter::sort_cpu(const cl::Buffer& keys, const cl::Buffer& values, std::size_t n, unsigned bits,
                           Profiler* profiler) {
  const std::size_t chunks = detail::cpu_chunk_count(runtime_, n, parameters_);
  const auto digit_bits = static_cast<unsigned>(parameters_.digit_bits);
  histogram_.resize((std::size_t{1} << digit_bits) * chunks);
  const auto passes = static_cast<unsigned>(div_up(bits, digit_bits));
  const bool use_spare = passes % 2 == 1 && passes > 1;  // see detail::radix_pass_target
  if (use_spare && n > spare_capacity_) {
    key_spare_ = runtime_.buffer(CL_MEM_READ_WRITE, n * key_bytes(key_type_), "radix sort spare key scratch");
    value_spare_ = with_values_
                       ? runtime_.buffer(CL_MEM_READ_WRITE, n * sizeof(cl_uint), "radix sort spare value scratch")
                       : value_scratch_;
    spare_capacity_ = n;
  }
  const auto n_arg = static_cast<cl_ulong>(n);
  const auto chunks_arg = static_cast<cl_uint>(chunks);
  // No host synchronisation between passes.
  cl::Buffer keys_in = keys, values_in = values;
  for (unsigned pass = 0; pass < passes; ++pass) {
    const detail::RadixTarget target = detail::radix_pass_target(pass, passes);
    const cl::Buffer& keys_out = target == detail::RadixTarget::Caller    ? keys
                                 : target == detail::RadixTarget::Scratch ? key_scratch_
                                                                          : key_spare_;
    const cl::Buffer& values_out = target == detail::RadixTarget::Caller    ? values
                                   : target == detail::RadixTarget::Scratch ? value_scratch_
                                                                            : value_spare_;
    const unsigned shift = pass * digit_bits;
    const auto radix = static_cast<cl_uint>(1u << std::min(digit_bits, bits - shift));
    const auto shift_arg = static_cast<cl_uint>(shift);
    detail::set_args(histogram_kernel_, keys_in, histogram_.buffer(), n_arg, chunks_arg, shift_arg, radix);
    enqueue_1d(runtime_.queue(), histogram_kernel_, chunks, 1, profiler, "radix histogram");
    detail::set_args(scatter_kernel_, keys_in, keys_out, values_in, values_out, histogram_.buffer(), n_arg, chunks_arg,
                     shift_arg, radix);
    enqueue_1d(runtime_.queue(), scatter_kernel_, chunks, 1, profiler, "radix scatter");
    keys_in = keys_out;
    values_in = values_out;
  }
  if (passes == 1) {
    // A single pass cannot write where it reads: copy its result back.
    cl::Event event;
    runtime_.queue().enqueueCopyBuffer(key_scratch_, keys, 0, 0, n * key_bytes(key_type_), nullptr, &event);
    if (profiler) profiler->add("radix copy back", event);
    if (with_values_) {
      runtime_.queue().enqueueCopyBuffer(value_scratch_, values, 0, 0, n * sizeof(cl_uint), nullptr, &event);
      if (profiler) profiler->add("radix copy back", event);
    }
  }
}

void RadixSorter::sort_gpu(const cl::Buffer& keys, const cl::Buffer& values, std::size_t n, unsigned bits,
                           Profiler* profiler) {
  const auto group = static_cast<std::size_t>(parameters_.group_size);
  const std::size_t blocks = div_up(n, group * static_cast<std::size_t>(parameters_.items_per_work_item));
  const std::size_t table_entries = (std::size_t{1} << kGpuDigitBits) * blocks;
  histogram_.resize(table_entries);
  const auto n_arg = static_cast<cl_ulong>(n);
  const auto blocks_arg = static_cast<cl_uint>(blocks);
  // Each pass sorts blocks into the scratch and scatters back, so the result ends in the caller's buffers.
  for (unsigned shift = 0; shift < bits; shift += kGpuDigitBits) {
    const auto digit_mask = static_cast<cl_uint>((1u << std::min(kGpuDigitBits, bits - shift)) - 1u);
    const auto shift_arg = static_cast<cl_uint>(shift);
    detail::set_args(histogram_kernel_, keys, values, key_scratch_, value_scratch_, histogram_.buffer(), n_arg, blocks_arg,
                     shift_arg, digit_mask);
    enqueue_1d(runtime_.queue(), histogram_kernel_, blocks * group, group, profiler, "radix block sort");
    table_scanner_->run(histogram_.buffer(), histogram_.buffer(), table_entries, ScanKind::Exclusive, false, profiler);
    detail::set_args(scatter_kernel_, key_scratch_, value_scratch_, keys, values, histogram_.buffer(), n_arg, blocks_arg,
                     shift_arg, digit_mask);
    enqueue_1d(runtime_.queue(), scatter_kernel_, blocks * group, group, profiler, "radix scatter");
  }
}

}  // namespace splatcl::primitives
